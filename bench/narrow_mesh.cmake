# The level mesh (dungeon.obj) is read through collide_io.
target_link_libraries(${target} PRIVATE collide_io)
