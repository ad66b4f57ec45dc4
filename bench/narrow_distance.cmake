# Box2D v3 beside Debian's 2.4 (box2d_v3/side.cmake).
include(${CMAKE_CURRENT_SOURCE_DIR}/box2d_v3/side.cmake)
