# Tests that hold a fast path to its general counterpart call internal routines
# (src/narrow/contact_routines.hpp).
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/src/narrow)
# Jolt as the oracle of jolt_oracle_test.cpp when the benchmarks configured it
# (cmake/peers.cmake), through collide_jolt_queries: Jolt's headers and instruction set stay out
# of this target's own sources.
if(TARGET collide_jolt_queries)
  target_link_libraries(${target} PRIVATE collide_jolt_queries)
  target_compile_definitions(${target} PRIVATE COLLIDE_HAVE_JOLT=1)
endif()
