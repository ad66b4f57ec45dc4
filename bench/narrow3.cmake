# Peers of bench_narrow3: Jolt behind collide_jolt_queries (cmake/peers.cmake), the only code
# compiled with Jolt's instruction set; libccd, FCL 0.7 and Bullet 3 from Debian. The workload
# and its exact reference come from tests/support (hull_pairs.hpp).
find_package(PkgConfig REQUIRED)
pkg_check_modules(COLLIDE_BULLET REQUIRED IMPORTED_TARGET bullet)
find_package(fcl REQUIRED)

set(narrow3_peers collide_jolt_queries PkgConfig::COLLIDE_BULLET fcl ccd)
target_link_libraries(${target} PRIVATE ${narrow3_peers})
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/tests)

# Like with like: collide compiled with Jolt's instruction set (AVX2, FMA, BMI, LZCNT, F16C),
# everything else as above. Built on request only (`--target bench_narrow3_avx2`): it compiles
# the whole library a second time.
set(COLLIDE_JOLT_ISA_FLAGS -mavx2 -mbmi -mpopcnt -mlzcnt -mf16c -mfma)
set(COLLIDE_JOLT_ISA_NAME "library compiled -mavx2 -mbmi -mpopcnt -mlzcnt -mf16c -mfma (Jolt's set)")
add_library(collide_avx2 STATIC EXCLUDE_FROM_ALL ${COLLIDE_SOURCES})
target_include_directories(collide_avx2 PUBLIC ${PROJECT_SOURCE_DIR}/include)
target_link_libraries(collide_avx2 PUBLIC glm::glm)
target_compile_options(collide_avx2 PRIVATE ${COLLIDE_JOLT_ISA_FLAGS} -fno-math-errno)
add_executable(bench_narrow3_avx2 EXCLUDE_FROM_ALL ${CMAKE_CURRENT_SOURCE_DIR}/narrow3.cpp)
target_link_libraries(bench_narrow3_avx2 PRIVATE collide_avx2 benchmark::benchmark ${narrow3_peers})
target_include_directories(bench_narrow3_avx2 PRIVATE ${PROJECT_SOURCE_DIR}/tests)
target_compile_definitions(bench_narrow3_avx2 PRIVATE COLLIDE_DATA_DIR="${COLLIDE_DATA_DIR}"
  "COLLIDE_BENCH_ISA=\"${COLLIDE_JOLT_ISA_NAME}\"")
