# The peer libraries kept as pinned sources in ../shared/peers (see its README.md): benchmark
# rivals and test oracles, never part of the library. The one home of their builds: included
# once from the top-level CMakeLists when the tests or the benchmarks are built. Every target
# here is EXCLUDE_FROM_ALL, so it is compiled only when a target that links it is (Jolt takes a
# few minutes on 2 cores: one configuration of it per build tree, linked by the benchmarks and
# by tests/oracles only).
#
# Link targets:
#  - `collide_jolt_queries`  Jolt's queries behind plain types (tests/support/jolt/
#                  jolt_queries.hpp; a world step's collision work and CharacterVirtual in
#                  jolt_world.hpp; PhysicsSystem::Update on a world of kinematic bodies in
#                  jolt_scale_world.hpp): the only code compiled with Jolt's headers and instruction
#                  set. Benchmarks and tests link this, not Jolt: Jolt's -m options are PUBLIC in
#                  its target, so every source of a target linking `Jolt::Jolt` would be
#                  compiled with them, collide's inline code included. Its INTERFACE defines
#                  COLLIDE_JOLT_AVX2=1 when Jolt uses AVX2 (a test checks the CPU before calling).
#  - `Jolt::Jolt`  Jolt Physics (3D) with its own default options: -mavx2 -mbmi -mpopcnt -mlzcnt
#                  -mf16c -mfma (USE_SSE4_1..USE_AVX2, USE_FMADD, USE_F16C, USE_LZCNT,
#                  USE_TZCNT), -ffp-contract=fast and -O3 in its own sources (its
#                  OVERRIDE_CXX_FLAGS). -DCOLLIDE_JOLT_SSE2=ON builds it for the x86-64 baseline
#                  (SSE2, collide's default build) instead. Benchmarks state both sides'
#                  instruction sets beside every ratio (jolt_queries::instruction_set()).
#                  Turned off: tests, samples, viewer, warnings-as-errors, profiler, debug
#                  renderer, object streams, GPU compute back ends, install rules, debug symbols,
#                  and link-time optimisation (an LTO static library would be re-optimised at
#                  the link of every executable that uses it). RTTI is on, as in the rest of the
#                  build, so that classes derived from Jolt's (collectors) link.
#  - `box2d_v3`    Box2D v3 (2D), built from its sources here rather than by add_subdirectory:
#                  its own CMake defines `box2d` and `box2d::box2d`, the names Debian's Box2D 2.4
#                  (find_package(box2d), linked as box2d::box2d to every bench and test) uses.
#                  Both libraries' headers are <box2d/box2d.h>: box2d_v3 puts its include folder
#                  first, so a source file sees one Box2D or the other, never both; the symbols do
#                  not clash (v3 is C, 2.4 is C++). SSE2, as Box2D's default (BOX2D_AVX2 off).
include_guard(GLOBAL)

set(COLLIDE_PEERS_DIR "${PROJECT_SOURCE_DIR}/../shared/peers" CACHE PATH
    "Pinned sources of the peer libraries (Jolt, Box2D v3) for benchmarks and test oracles")
option(COLLIDE_JOLT_SSE2 "Build Jolt on the x86-64 baseline (SSE2) instead of its AVX2/FMA default"
       OFF)
if(NOT EXISTS "${COLLIDE_PEERS_DIR}/jolt/Build/CMakeLists.txt" OR
   NOT EXISTS "${COLLIDE_PEERS_DIR}/box2d/src")
  message(WARNING "collide: no peer sources in ${COLLIDE_PEERS_DIR}: Jolt and Box2D v3 are not "
                  "built; the benchmarks that race them and tests/oracles are left out")
  return()
endif()

# ---- Jolt ---------------------------------------------------------------------------------------
foreach(opt TARGET_UNIT_TESTS TARGET_HELLO_WORLD TARGET_PERFORMANCE_TEST TARGET_SAMPLES
            TARGET_VIEWER ENABLE_ALL_WARNINGS PROFILER_IN_DEBUG_AND_RELEASE
            DEBUG_RENDERER_IN_DEBUG_AND_RELEASE ENABLE_OBJECT_STREAM INTERPROCEDURAL_OPTIMIZATION
            ENABLE_INSTALL GENERATE_DEBUG_SYMBOLS JPH_USE_DX12 JPH_USE_VK JPH_USE_MTL
            JPH_USE_CPU_COMPUTE)
  set(${opt} OFF CACHE BOOL "" FORCE)
endforeach()
set(CPP_RTTI_ENABLED ON CACHE BOOL "" FORCE)
set(_collide_jolt_simd USE_SSE4_1 USE_SSE4_2 USE_AVX USE_AVX2 USE_LZCNT USE_TZCNT USE_F16C
                       USE_FMADD)
foreach(opt IN LISTS _collide_jolt_simd)
  if(COLLIDE_JOLT_SSE2)
    set(${opt} OFF CACHE BOOL "" FORCE)
  else()
    set(${opt} ON CACHE BOOL "" FORCE)
  endif()
endforeach()
set(USE_AVX512 OFF CACHE BOOL "" FORCE)
add_subdirectory(${COLLIDE_PEERS_DIR}/jolt/Build ${CMAKE_BINARY_DIR}/peers/jolt EXCLUDE_FROM_ALL)

# Jolt's queries behind plain types (tests/support/jolt/jolt_queries.hpp, jolt_world.hpp), for
# benchmarks and tests: the one library compiled with Jolt's headers and instruction set.
add_library(collide_jolt_queries STATIC EXCLUDE_FROM_ALL
            ${PROJECT_SOURCE_DIR}/tests/support/jolt/jolt_queries.cpp
            ${PROJECT_SOURCE_DIR}/tests/support/jolt/jolt_world.cpp
            ${PROJECT_SOURCE_DIR}/tests/support/jolt/jolt_scale_world.cpp)
target_link_libraries(collide_jolt_queries PRIVATE Jolt::Jolt)
target_include_directories(collide_jolt_queries PUBLIC ${PROJECT_SOURCE_DIR}/tests)
if(NOT COLLIDE_JOLT_SSE2)
  target_compile_definitions(collide_jolt_queries INTERFACE COLLIDE_JOLT_AVX2=1)
endif()

# ---- Box2D v3 -----------------------------------------------------------------------------------
enable_language(C)
file(GLOB _collide_box2d_v3_sources CONFIGURE_DEPENDS ${COLLIDE_PEERS_DIR}/box2d/src/*.c)
add_library(box2d_v3 STATIC EXCLUDE_FROM_ALL ${_collide_box2d_v3_sources})
target_include_directories(box2d_v3 BEFORE PUBLIC ${COLLIDE_PEERS_DIR}/box2d/include
                                        PRIVATE ${COLLIDE_PEERS_DIR}/box2d/src)
set_target_properties(box2d_v3 PROPERTIES C_STANDARD 17 C_STANDARD_REQUIRED YES C_EXTENSIONS YES
                                          C_VISIBILITY_PRESET hidden)
target_compile_options(box2d_v3 PRIVATE $<$<C_COMPILER_ID:GNU,Clang>:-ffp-contract=off>)
target_link_libraries(box2d_v3 PUBLIC m)
# Its instruction set, for the context block beside every ratio (bench/instruction_set.hpp): the
# default x86-64 compile (no -m options, as collide's) selects v3's SSE2 path in src/core.h.
target_compile_definitions(box2d_v3 INTERFACE
  "COLLIDE_BOX2D_V3_ISA=\"SSE2, the x86-64 baseline: B2_SIMD_SSE2 4-wide contact solver of v3, BOX2D_AVX2 off\"")
