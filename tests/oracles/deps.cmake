# Peer libraries as oracles of collide's 3D queries on the same inputs: Jolt through
# collide_jolt_queries (cmake/peers.cmake; its instruction set stays in that library), and
# Bullet 3 from Debian. Only this test executable links Jolt, so the other tests build without
# waiting for it.
find_package(PkgConfig REQUIRED)
pkg_check_modules(COLLIDE_BULLET REQUIRED IMPORTED_TARGET bullet)
target_link_libraries(${target} PRIVATE collide_jolt_queries PkgConfig::COLLIDE_BULLET)
