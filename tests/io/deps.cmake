target_link_libraries(${target} PRIVATE collide_io)
target_compile_definitions(${target} PRIVATE COLLIDE_EXAMPLES_DIR="${PROJECT_SOURCE_DIR}/examples")
# The fuzz targets' checks (fuzz/*_check.hpp) replay the inputs the fuzzer found.
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/fuzz)
target_compile_definitions(${target} PRIVATE COLLIDE_FUZZ_DIR="${PROJECT_SOURCE_DIR}/fuzz")
# tinyobjloader: an independent OBJ reader, the oracle for collide_io's own (obj_oracle_test.cpp).
find_package(tinyobjloader REQUIRED)
target_link_libraries(${target} PRIVATE tinyobjloader::tinyobjloader)
