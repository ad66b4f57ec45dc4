#pragma once
/// @file
/// Wavefront OBJ level meshes (through tinyobjloader) as triangle soups for the walk mesh.

#include <collide/walkmesh/walk_mesh.hpp>

#include <string>

namespace collide::io {

/// Loads every face of an OBJ file as triangles (polygons are fan-triangulated by tinyobjloader),
/// positions in the file's units and axes. The soup's `name` is the file name, so errors from
/// `build_walk_mesh` / `make_walk_mesh` name the file. Throws InvalidInput naming the file when it
/// cannot be read or parsed, has a non-finite vertex, or has no triangles.
[[nodiscard]] TriangleSoup load_obj(const std::string& path);

}  // namespace collide::io
