# Peers of bench_world3d: Jolt's PhysicsSystem pieces and CharacterVirtual behind
# collide_jolt_queries (tests/support/jolt/jolt_world.hpp; cmake/peers.cmake: the only code
# compiled with Jolt's instruction set). The level (dungeon.obj) is read through collide_io.
target_link_libraries(${target} PRIVATE collide_io collide_jolt_queries)
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
