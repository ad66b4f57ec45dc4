# The level mesh (dungeon.obj) is read through collide_io; the peer is Jolt's MeshShape behind
# collide_jolt_queries (cmake/peers.cmake, Jolt's own instruction set).
target_link_libraries(${target} PRIVATE collide_io collide_jolt_queries)
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
