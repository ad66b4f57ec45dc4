# HACD (Bullet 3.24 Extras, Debian's libbullet-extras-dev) is the peer; no cmake config: link
# libHACD (double precision, HACD::Real) by name, headers under /usr/include/bullet.
find_path(COLLIDE_HACD_INCLUDE HACD/hacdHACD.h PATH_SUFFIXES bullet REQUIRED)
find_library(COLLIDE_HACD_LIBRARY HACD REQUIRED)
target_include_directories(${target} SYSTEM PRIVATE ${COLLIDE_HACD_INCLUDE})
target_link_libraries(${target} PRIVATE ${COLLIDE_HACD_LIBRARY} collide_io)
