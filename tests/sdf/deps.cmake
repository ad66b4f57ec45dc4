# Mesh fields read real levels (dungeon.obj) through io.
target_link_libraries(${target} PRIVATE collide_io)
