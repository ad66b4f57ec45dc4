# cmake -DWORK_DIR=<scratch dir> -P check_layers_catches.cmake   (ctest: layers.catches_faults)
# The layering check must be able to fail: it runs on a made-up tree holding one fault of each
# rule (and look-alikes that are not faults) and must report exactly those faults, and an
# exception that matches nothing as stale.
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/layer_rules.cmake)

set(root ${WORK_DIR})
file(REMOVE_RECURSE ${root})
function(put path)
  string(JOIN "\n" text ${ARGN})
  file(WRITE ${root}/${path} "${text}\n")
endfunction()

put(DESIGN.md "# design" "## Layers (data flows top to bottom)" "```" " apps/      the tool"
    " io/        file formats" " draw/      pictures" " world/     worlds" " shape/     shapes"
    " core/      basics" "```" "## Next" "```" " ignored/  not a layer" "```")
# Faults, one per rule.
put(include/collide/core/low.hpp "#include <collide/shape/circle.hpp>")        # higher-layer
put(src/shape/circle.cpp "#include <collide/draw/palette.hpp>")                 # other-target
put(src/world/world.cpp "#include \"../shape/private.hpp\"")                    # private-header
put(include/collide/shape/circle.hpp "namespace collide::detail {" "}")         # detail-name
put(include/collide/world/world.hpp "inline int f() { return detail::g(); }")   # detail-name
put(src/extra/extra.cpp "int x;")                                               # unknown-folder
put(io/src/tiled.cpp "#include <collide/draw/palette.hpp>")                     # other-target
put(draw/src/cairo_picture.cpp "#include \"sub/inner.hpp\"")                    # private-header
# Not faults: lower and own layers, a file beside the includer, detail in comments and in
# private files, a target including the library and itself.
put(src/shape/private.hpp "namespace collide::detail {}")
put(src/shape/shape.cpp "#include <collide/core/low.hpp>" "#include <collide/shape/circle.hpp>"
    "#include \"private.hpp\"" "// detail::see_private")
put(include/collide/core/doc.hpp "/// Details: see detail:: in the sources." "int y; // detail::z")
put(draw/include/collide/draw/palette.hpp "#include <collide/core/low.hpp>")
put(draw/src/sub/inner.hpp "")
put(draw/src/picture.cpp "#include <collide/draw/palette.hpp>" "#include <collide/world/world.hpp>")

collide_layers_from_design(${root}/DESIGN.md layers)
set(expected_layers core shape world draw io apps)
if(NOT layers STREQUAL expected_layers)
  message(FATAL_ERROR "layers read from the diagram: '${layers}', expected '${expected_layers}'")
endif()

collide_check_layers(ROOT ${root} LAYERS core shape world TARGETS draw io
                     EXCEPTIONS "src/world/world.cpp: private-header" "src/shape/shape.cpp: private-header"
                     VIOLATIONS violations STALE stale)
set(expected_violations
  "draw/src/cairo_picture.cpp: private-header"
  "include/collide/core/low.hpp: higher-layer"
  "include/collide/shape/circle.hpp: detail-name"
  "include/collide/world/world.hpp: detail-name"
  "io/src/tiled.cpp: other-target"
  "src/extra/extra.cpp: unknown-folder"
  "src/shape/circle.cpp: other-target")
set(keys)
foreach(v IN LISTS violations)
  string(REGEX MATCH "^[^:]+: [a-z-]+" key "${v}")
  list(APPEND keys "${key}")
endforeach()
list(SORT keys)
if(NOT keys STREQUAL expected_violations)
  string(REPLACE ";" "\n  " got "${violations}")
  string(REPLACE ";" "\n  " want "${expected_violations}")
  message(FATAL_ERROR "violations found:\n  ${got}\nexpected:\n  ${want}")
endif()
if(NOT stale STREQUAL "src/shape/shape.cpp: private-header")
  message(FATAL_ERROR "stale exceptions: '${stale}', expected the one for src/shape/shape.cpp")
endif()
list(LENGTH violations n)
message(STATUS "the layering check reports all ${n} planted faults, and the stale exception")
