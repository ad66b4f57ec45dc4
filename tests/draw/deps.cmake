# tests/draw holds the tests of collide_draw (draw/), the pictures target.
target_link_libraries(${target} PRIVATE collide_draw)
# pugixml parses the SVG documents: they must be well-formed XML.
find_package(pugixml REQUIRED)
target_link_libraries(${target} PRIVATE pugixml::pugixml)
