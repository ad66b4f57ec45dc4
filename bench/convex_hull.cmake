# Peer: Jolt's ConvexHullBuilder and ConvexHullShape support function, behind
# collide_jolt_queries (cmake/peers.cmake: Jolt's own instruction set, AVX2 by default).
target_link_libraries(${target} PRIVATE collide_jolt_queries)
