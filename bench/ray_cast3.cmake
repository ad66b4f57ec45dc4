# Peer of bench_ray_cast3: Jolt's convex shapes behind collide_jolt_queries (cmake/peers.cmake),
# the only code compiled with Jolt's instruction set.
target_link_libraries(${target} PRIVATE collide_jolt_queries)

# Like with like, as bench_narrow3_avx2 (narrow3.cmake, processed before this file): collide
# compiled with Jolt's instruction set. Built on request only (`--target bench_ray_cast3_avx2`).
if(TARGET collide_avx2)
  add_executable(bench_ray_cast3_avx2 EXCLUDE_FROM_ALL ${CMAKE_CURRENT_SOURCE_DIR}/ray_cast3.cpp)
  target_link_libraries(bench_ray_cast3_avx2 PRIVATE collide_avx2 benchmark::benchmark collide_jolt_queries)
  target_include_directories(bench_ray_cast3_avx2 PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  target_compile_definitions(bench_ray_cast3_avx2 PRIVATE COLLIDE_DATA_DIR="${COLLIDE_DATA_DIR}"
    "COLLIDE_BENCH_ISA=\"${COLLIDE_JOLT_ISA_NAME}\"")
endif()
