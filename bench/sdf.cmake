# Peer of bench_sdf: OpenVDB 10 (Debian libopenvdb-dev). Debian ships FindOpenVDB.cmake (under
# /usr/lib/x86_64-linux-gnu/cmake/OpenVDB) but no config, and that module wants Boost.Iostreams'
# development files, which the build does not need: link the library directly, with the TBB and
# Imath its headers use (TBB's CMake config; Imath's through pkg-config, as Debian's Imath config
# names a Python module that is not installed). Its headers include Boost headers that
# libopenvdb-dev does not depend on (libboost-dev, scripts/install-deps).
find_package(TBB CONFIG REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(COLLIDE_IMATH REQUIRED IMPORTED_TARGET Imath)
find_path(COLLIDE_OPENVDB_INCLUDE_DIR openvdb/openvdb.h REQUIRED)
find_library(COLLIDE_OPENVDB_LIBRARY openvdb REQUIRED)
target_include_directories(${target} SYSTEM PRIVATE ${COLLIDE_OPENVDB_INCLUDE_DIR})
target_link_libraries(${target} PRIVATE collide_io ${COLLIDE_OPENVDB_LIBRARY} TBB::tbb PkgConfig::COLLIDE_IMATH)
target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
