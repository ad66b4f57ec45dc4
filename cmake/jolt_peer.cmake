# Jolt Physics (../shared/peers/jolt, MIT) as a benchmark rival and test oracle; never part of the
# library. Include this file from a bench/NAME.cmake or tests/DIR/deps.cmake and link `Jolt`:
# the library is configured once per build tree however many files include it, and built only
# when a target that links it is.
#
# Jolt's SIMD options (SSE4.1 up to AVX2, FMA, F16C, LZCNT, TZCNT) are turned off so that it runs
# on the same instruction set as collide's default build: the x86-64 baseline, SSE2. State that
# beside every ratio. Its warnings, profiler, debug renderer, GPU back ends and install rules
# are off, and OVERRIDE_CXX_FLAGS is off so it keeps the build type's flags.
if(NOT TARGET Jolt)
  set(COLLIDE_JOLT_DIR "${PROJECT_SOURCE_DIR}/../shared/peers/jolt" CACHE PATH
      "Jolt Physics sources (a peer for benchmarks and tests)")
  foreach(opt TARGET_UNIT_TESTS TARGET_HELLO_WORLD TARGET_PERFORMANCE_TEST TARGET_SAMPLES
              TARGET_VIEWER ENABLE_ALL_WARNINGS PROFILER_IN_DEBUG_AND_RELEASE
              DEBUG_RENDERER_IN_DEBUG_AND_RELEASE OVERRIDE_CXX_FLAGS INTERPROCEDURAL_OPTIMIZATION
              ENABLE_INSTALL GENERATE_DEBUG_SYMBOLS USE_SSE4_1 USE_SSE4_2 USE_AVX USE_AVX2
              USE_AVX512 USE_LZCNT USE_TZCNT USE_F16C USE_FMADD JPH_USE_DX12 JPH_USE_VK
              JPH_USE_MTL JPH_USE_CPU_COMPUTE)
    set(${opt} OFF CACHE BOOL "" FORCE)
  endforeach()
  add_subdirectory(${COLLIDE_JOLT_DIR}/Build ${CMAKE_BINARY_DIR}/peers/jolt EXCLUDE_FROM_ALL)
endif()
