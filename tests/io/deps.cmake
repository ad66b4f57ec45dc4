target_link_libraries(${target} PRIVATE collide_io)
target_compile_definitions(${target} PRIVATE COLLIDE_EXAMPLES_DIR="${PROJECT_SOURCE_DIR}/examples")
