# Peers of bench_broad_phase: Bullet (btDbvtBroadphase, btAxisSweep3), Chipmunk 7 (cpSpaceHash,
# cpBBTree) and FCL 0.7 (spatial hashing and dynamic AABB tree managers). Box2D is linked to
# every bench already.
find_package(PkgConfig REQUIRED)
pkg_check_modules(COLLIDE_BULLET REQUIRED IMPORTED_TARGET bullet)
find_package(fcl REQUIRED)
target_link_libraries(${target} PRIVATE PkgConfig::COLLIDE_BULLET fcl chipmunk)
# Box2D v3's b2DynamicTree (box2d_v3/side.cmake).
include(${CMAKE_CURRENT_SOURCE_DIR}/box2d_v3/side.cmake)
