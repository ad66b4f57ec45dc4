# Box2D v3's side of the 2D query benchmarks, one static library for every bench that races it
# beside Debian's 2.4 (include this from NAME.cmake). v3's headers reach only queries.cpp: the
# library links box2d_v3 (cmake/peers.cmake) privately, so a bench's own sources keep 2.4's
# <box2d/box2d.h>. The v3 instruction set (COLLIDE_BOX2D_V3_ISA) is passed on for the context.
if(NOT TARGET collide_bench_box2d_v3)
  add_library(collide_bench_box2d_v3 STATIC ${CMAKE_CURRENT_LIST_DIR}/queries.cpp)
  target_link_libraries(collide_bench_box2d_v3 PUBLIC collide::collide benchmark::benchmark
                                               PRIVATE box2d_v3)
  target_compile_definitions(collide_bench_box2d_v3 PUBLIC
                             $<TARGET_PROPERTY:box2d_v3,INTERFACE_COMPILE_DEFINITIONS>)
endif()
target_link_libraries(${target} PRIVATE collide_bench_box2d_v3)
