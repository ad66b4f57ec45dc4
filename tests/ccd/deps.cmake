# The shared level meshes are read through collide_io (OBJ) for the mesh ray cast tests.
target_link_libraries(${target} PRIVATE collide_io)
