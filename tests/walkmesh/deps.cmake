target_link_libraries(${target} PRIVATE collide_io)
