# Chipmunk 7's cpPolylineConvexDecomposition is the peer (no cmake config: link `chipmunk`).
target_link_libraries(${target} PRIVATE chipmunk)
