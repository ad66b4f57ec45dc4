# Debian's qhull (libqhull_r, reentrant, double) is the oracle for ConvexHull: volumes and
# extreme-point sets. Test-only; the library never links it.
# Its wrapper (plain types in, plain types out) sits with the other oracle wrappers in tests/support.
target_sources(${target} PRIVATE ${PROJECT_SOURCE_DIR}/tests/support/qhull/qhull_oracle.cpp)
target_link_libraries(${target} PRIVATE qhull_r)
# The fuzz targets' checks (fuzz/*_check.hpp) replay the inputs the fuzzer found.
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/fuzz)
target_compile_definitions(${target} PRIVATE COLLIDE_FUZZ_DIR="${PROJECT_SOURCE_DIR}/fuzz")
