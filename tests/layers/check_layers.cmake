# cmake -DSOURCE_DIR=<repo root> -P check_layers.cmake   (ctest: layers.check, label `layers`)
# Fails if the layering of DESIGN.md does not hold in the sources (rules in layer_rules.cmake):
# the library proper (include/collide, src/) includes only its own layer and those below it,
# never collide_draw or collide_io, never another folder's private files, and its public headers
# name no detail::. The layers and their order are read from DESIGN.md's diagram.
cmake_minimum_required(VERSION 3.20)  # policies of a -P script (IN_LIST)
include(${CMAKE_CURRENT_LIST_DIR}/layer_rules.cmake)

# Known exceptions, "PATH: RULE": faults being fixed elsewhere. Each must still occur (a fixed
# one fails the check until it is removed here, so it cannot come back unnoticed). Empty it.
set(KNOWN_LAYER_EXCEPTIONS)

collide_layers_from_design(${SOURCE_DIR}/DESIGN.md design_layers)
set(layers)
set(targets)
foreach(name IN LISTS design_layers)
  if(IS_DIRECTORY ${SOURCE_DIR}/src/${name} OR IS_DIRECTORY ${SOURCE_DIR}/include/collide/${name})
    list(APPEND layers ${name})
  elseif(IS_DIRECTORY ${SOURCE_DIR}/${name}/include/collide/${name})
    list(APPEND targets ${name})
  endif()
endforeach()
# The diagram must have been read: the library's bottom and top, and both other targets.
foreach(expected core world)
  if(NOT expected IN_LIST layers)
    message(FATAL_ERROR "layer '${expected}' not found in DESIGN.md's diagram (read: ${design_layers})")
  endif()
endforeach()
foreach(expected draw io)
  if(NOT expected IN_LIST targets)
    message(FATAL_ERROR "target '${expected}' not found in DESIGN.md's diagram (read: ${design_layers})")
  endif()
endforeach()

collide_check_layers(ROOT ${SOURCE_DIR} LAYERS ${layers} TARGETS ${targets}
                     EXCEPTIONS ${KNOWN_LAYER_EXCEPTIONS} VIOLATIONS violations STALE stale)
list(JOIN layers " < " order)
message(STATUS "layers ${order}; targets ${targets}: ${COLLIDE_LAYERS_FILES_CHECKED} files checked")
set(failed OFF)
foreach(v IN LISTS violations)
  message(SEND_ERROR "layering: ${v}")
  set(failed ON)
endforeach()
foreach(e IN LISTS stale)
  message(SEND_ERROR "layering: known exception \"${e}\" no longer occurs: remove it from KNOWN_LAYER_EXCEPTIONS (tests/layers/check_layers.cmake)")
  set(failed ON)
endforeach()
if(failed)
  message(FATAL_ERROR "the layering of DESIGN.md does not hold (see above)")
endif()
