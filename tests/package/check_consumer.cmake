# cmake -DSOURCE_DIR=... -DBUILD_DIR=... -DWORK_DIR=... -DMODE=find_package|add_subdirectory -P
# Installs collide into a scratch prefix (find_package mode) or vendors it (add_subdirectory
# mode), then configures, builds and runs the consumer project, with the build's own
# CMAKE_CXX_FLAGS (CXX_FLAGS): a sanitizer build's library links only into a sanitized consumer.
file(REMOVE_RECURSE ${WORK_DIR})
if(MODE STREQUAL "find_package")
  execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix
                  RESULT_VARIABLE rc OUTPUT_QUIET)
  if(rc)
    message(FATAL_ERROR "install failed")
  endif()
  set(configure_args -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
else()
  set(configure_args -DCOLLIDE_SOURCE_DIR=${SOURCE_DIR})
endif()
# Build type None (no optimisation flags of its own): this checks that a game can configure,
# build, link and run against collide, not how fast; vendored, the library is compiled again.
# It stays the release suite's long pole, sharing two cores with the other tests: 202 s at -O3,
# 185 s unoptimised (stop 67, a slow phase of the host).
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/consumer
                        -B ${WORK_DIR}/build -DCMAKE_BUILD_TYPE=None ${configure_args}
                        "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}"
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "consumer configure failed (${MODE})")
endif()
# Only the consumer and what it links: vendored, collide's other libraries (io, draw) would be
# built too, which the main build has done already, and this test was the suite's long pole
# (240 s of a 200 s release run, 520 s under the sanitizers).
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build --target consumer --parallel 2 RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "consumer build failed (${MODE})")
endif()
execute_process(COMMAND ${WORK_DIR}/build/consumer RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "consumer run failed (${MODE})")
endif()
