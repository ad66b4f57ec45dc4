# Peers of bench_world_scale: Box2D v3 (cmake/peers.cmake: box2d_v3, its include folder first, so
# <box2d/box2d.h> in world_scale.cpp is v3's; Debian's 2.4 that every bench links is not included
# by it), collide's scene builder (collide_cli_lib: cli::make_scene) and oneTBB for v3's task
# callbacks.
find_package(TBB CONFIG REQUIRED)
target_link_libraries(${target} PRIVATE box2d_v3 collide_cli_lib TBB::tbb)
