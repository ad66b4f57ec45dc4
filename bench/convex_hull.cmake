# Peer: Jolt's ConvexHullBuilder and ConvexHullShape support function (SSE2 build, see
# cmake/jolt_peer.cmake).
include(${PROJECT_SOURCE_DIR}/cmake/jolt_peer.cmake)
target_link_libraries(${target} PRIVATE Jolt)
