# Peer of bench_ray_cast3: Jolt's convex shapes behind collide_jolt_queries (cmake/peers.cmake),
# the only code compiled with Jolt's instruction set.
target_link_libraries(${target} PRIVATE collide_jolt_queries)
