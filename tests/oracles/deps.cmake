# Peer libraries as oracles of collide's 3D queries on the same inputs: Jolt through
# collide_jolt_queries (cmake/peers.cmake; its instruction set stays in that library). Only
# this test executable links Jolt, so the other tests build without waiting for it.
target_link_libraries(${target} PRIVATE collide_jolt_queries)
