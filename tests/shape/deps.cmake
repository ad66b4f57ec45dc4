# Debian's qhull (libqhull_r, reentrant, double) is the oracle for ConvexHull: volumes and
# extreme-point sets. Test-only; the library never links it.
target_link_libraries(${target} PRIVATE qhull_r)
