# The shared level meshes are read through collide_io (OBJ) for the mesh ray cast tests.
target_link_libraries(${target} PRIVATE collide_io)
# The hull ray cast's lane clip is held to the scalar Cyrus-Beck loop it replaces
# (src/ccd/clip_ray.hpp).
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/src/ccd)
