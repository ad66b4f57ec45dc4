# World3D reads a real level (dungeon.obj) through io.
target_link_libraries(${target} PRIVATE collide_io)
