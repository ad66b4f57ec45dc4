# Peers of bench_mesh_raycast: Jolt's MeshShape behind collide_jolt_queries (cmake/peers.cmake,
# Jolt's own instruction set) and Embree 3 (Debian libembree-dev; kernels chosen at run time).
# collide's side loads the levels through collide_io; the reference is tests/support.
find_package(embree 3 REQUIRED)
target_link_libraries(${target} PRIVATE collide_io collide_jolt_queries embree)
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
