target_link_libraries(${target} PRIVATE collide_cli_lib)
target_compile_definitions(${target} PRIVATE COLLIDE_CLI_PATH="$<TARGET_FILE:collide_cli>"
                                             COLLIDE_EXAMPLES_DIR="${PROJECT_SOURCE_DIR}/examples")
add_dependencies(${target} collide_cli)
# pugixml parses the SVG pictures of `collide cast`.
find_package(pugixml REQUIRED)
target_link_libraries(${target} PRIVATE pugixml::pugixml)
# The fuzz targets' checks (fuzz/*_check.hpp) replay the inputs the fuzzer found.
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/fuzz)
target_compile_definitions(${target} PRIVATE COLLIDE_FUZZ_DIR="${PROJECT_SOURCE_DIR}/fuzz")
