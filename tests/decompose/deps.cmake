# Real meshes (FCL models) read through io.
target_link_libraries(${target} PRIVATE collide_io)
