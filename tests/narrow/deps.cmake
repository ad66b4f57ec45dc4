# Tests that hold a fast path to its general counterpart call internal routines
# (src/narrow/contact_routines.hpp).
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/src/narrow)
