# HACD (Bullet 3.24 Extras, Debian's libbullet-extras-dev) is the peer; no cmake config: link
# libHACD (double precision, HACD::Real) by name, headers under /usr/include/bullet.
find_path(COLLIDE_HACD_INCLUDE HACD/hacdHACD.h PATH_SUFFIXES bullet REQUIRED)
find_library(COLLIDE_HACD_LIBRARY HACD REQUIRED)
target_include_directories(${target} SYSTEM PRIVATE ${COLLIDE_HACD_INCLUDE})
target_link_libraries(${target} PRIVATE ${COLLIDE_HACD_LIBRARY} collide_io)
# V-HACD 2.x from Debian's Bullet source (vhacd/peer.cmake).
include(${CMAKE_CURRENT_SOURCE_DIR}/vhacd/peer.cmake)
if(COLLIDE_HAVE_VHACD)
  target_link_libraries(${target} PRIVATE collide_vhacd_peer)
endif()
target_compile_definitions(${target} PRIVATE COLLIDE_HAVE_VHACD=${COLLIDE_HAVE_VHACD})
