# Peers of bench_world_scale3d: Jolt's PhysicsSystem behind collide_jolt_queries
# (tests/support/jolt/jolt_scale_world.hpp; cmake/peers.cmake: the only code compiled with Jolt's
# instruction set) and collide's 3D scene builder (collide_cli_lib: cli::make_scene3d).
target_link_libraries(${target} PRIVATE collide_cli_lib collide_jolt_queries)
