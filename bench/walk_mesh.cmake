# Peer: Recast/Detour (Debian librecast-dev). Our side loads the level through collide_io.
target_link_libraries(${target} PRIVATE collide_io Recast Detour)
target_include_directories(${target} PRIVATE /usr/include/recastnavigation)
