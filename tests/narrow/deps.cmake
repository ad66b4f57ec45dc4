# Tests that hold a fast path to its general counterpart call internal routines
# (src/narrow/contact_routines.hpp).
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/src/narrow)
# The shared level meshes are read through collide_io (OBJ) for the mesh query tests.
target_link_libraries(${target} PRIVATE collide_io)
