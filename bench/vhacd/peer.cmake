# V-HACD 2.x (Mamou, volumetric hierarchical approximate convex decomposition; the version
# pybullet ships as pybullet.vhacd, Bullet 3.24's Extras/VHACD, BSD-3-Clause), a rival of
# bench_decompose_mesh. Debian builds Bullet without it, so it is compiled here from Debian's
# own source of Bullet 3.24 (the orig tarball of the package libbullet-extras-dev is built from,
# fetched from the Debian archive at configure time and checked against the archive's SHA-256).
# The build stays whole without it: when the archive cannot be reached, a warning says so and
# the benchmark runs collide and HACD only (COLLIDE_HAVE_VHACD 0).
#
# Defines `collide_vhacd_peer` (static, single-threaded: without OpenMP, as pybullet builds it;
# collide's rows run on one thread too) and sets COLLIDE_HAVE_VHACD.
set(COLLIDE_VHACD_TARBALL_NAME bullet_3.24+dfsg.orig.tar.xz)
set(COLLIDE_VHACD_TARBALL_SHA256 43c1edae2024ba18bb5d7bfd3bb2394b066a79151a29789504a2d8efcdc333d7)
set(COLLIDE_VHACD_DIR ${CMAKE_BINARY_DIR}/peers/vhacd)
set(COLLIDE_VHACD_SOURCE ${COLLIDE_VHACD_DIR}/bullet3-3.24/Extras/VHACD)
set(COLLIDE_HAVE_VHACD 0)
if(NOT EXISTS ${COLLIDE_VHACD_SOURCE}/src/VHACD.cpp)
  set(tarball ${COLLIDE_VHACD_DIR}/${COLLIDE_VHACD_TARBALL_NAME})
  foreach(mirror http://deb.debian.org/debian
                 https://snapshot.debian.org/archive/debian/20250520T000000Z)
    if(NOT EXISTS ${tarball})
      file(DOWNLOAD ${mirror}/pool/main/b/bullet/${COLLIDE_VHACD_TARBALL_NAME} ${tarball}.part
           STATUS status TIMEOUT 120)
      list(GET status 0 code)
      if(code EQUAL 0)
        file(SHA256 ${tarball}.part sha)
        if(sha STREQUAL COLLIDE_VHACD_TARBALL_SHA256)
          file(RENAME ${tarball}.part ${tarball})
        else()
          message(WARNING "V-HACD peer: ${mirror} gave a tarball with SHA-256 ${sha}, not ${COLLIDE_VHACD_TARBALL_SHA256}")
        endif()
      endif()
      file(REMOVE ${tarball}.part)
    endif()
  endforeach()
  if(EXISTS ${tarball})
    file(ARCHIVE_EXTRACT INPUT ${tarball} DESTINATION ${COLLIDE_VHACD_DIR}
         PATTERNS bullet3-3.24/Extras/VHACD)
  endif()
endif()
if(EXISTS ${COLLIDE_VHACD_SOURCE}/src/VHACD.cpp)
  if(NOT TARGET collide_vhacd_peer)
    file(GLOB vhacd_sources ${COLLIDE_VHACD_SOURCE}/src/*.cpp)
    add_library(collide_vhacd_peer STATIC EXCLUDE_FROM_ALL ${vhacd_sources})
    target_include_directories(collide_vhacd_peer SYSTEM PUBLIC ${COLLIDE_VHACD_SOURCE}/public
                               PRIVATE ${COLLIDE_VHACD_SOURCE}/inc)
    # Its own code, not ours: no warnings (it has many), its btConvexHullComputer from Debian's
    # Bullet (LinearMath).
    target_compile_options(collide_vhacd_peer PRIVATE -w)
    find_package(PkgConfig REQUIRED)
    pkg_check_modules(COLLIDE_BULLET REQUIRED IMPORTED_TARGET bullet)
    target_link_libraries(collide_vhacd_peer PRIVATE PkgConfig::COLLIDE_BULLET)
  endif()
  set(COLLIDE_HAVE_VHACD 1)
else()
  message(WARNING "V-HACD peer: Debian's ${COLLIDE_VHACD_TARBALL_NAME} could not be fetched; "
                  "bench_decompose_mesh runs without V-HACD")
endif()
