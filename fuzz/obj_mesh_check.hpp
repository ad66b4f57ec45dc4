#pragma once
// What must hold for any bytes given to the OBJ readers as a file (fuzz_obj_mesh, and the
// regression test that replays the inputs the fuzzer found): shared so both check the same.

#include "fuzz_check.hpp"

#include <collide/ccd/raycast.hpp>
#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/sdf/distance_field.hpp>
#include <collide/shape/sphere.hpp>
#include <collide/walkmesh/make_walk_mesh.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>

namespace collide::fuzz {

/// Distance fields of an accepted mesh (what `collide sdf` builds), dense and sparse, at a sixth
/// of its largest extent (a few thousand nodes, so either way to the band may run): built, or
/// refused with InvalidInput (a flat mesh's voxel of 0); every value built is finite.
inline std::string check_mesh_fields(const TriangleMesh& mesh) {
  const Aabb3 box = compute_aabb(mesh, Transform3{});
  const Vec3 size = box.max - box.min;
  FieldOptions options;
  options.voxel = std::max({size.x, size.y, size.z}) / 6.0f;
  options.max_bytes = std::size_t{16} << 20;
  try {
    const DistanceField3 dense = make_distance_field(mesh, options);
    for (const float d : dense.distances) {
      if (!std::isfinite(d)) return "a distance field of an accepted mesh holds a value that is not finite";
    }
    for (const Vec3& c : dense.closest_points) {
      if (!is_finite(c)) return "a distance field of an accepted mesh holds a closest point that is not finite";
    }
    const SparseDistanceField3 sparse = make_sparse_distance_field(mesh, options);
    for (const float d : sparse.bricks) {
      if (!std::isfinite(d)) return "a sparse distance field of an accepted mesh holds a value that is not finite";
    }
  } catch (const InvalidInput& e) {
    if (std::string_view(e.what()).empty()) return "a distance field was refused without a message";
  } catch (const std::exception& e) {
    return std::string("a distance field build threw other than InvalidInput: ") + e.what();
  }
  return {};
}

/// "" when `input`, written to a file, is handled as collide/io/obj.hpp says, else what went
/// wrong:
///  - io::load_obj throws nothing but InvalidInput naming the file; a soup it accepts has
///    triangles, finite positions and every index in range;
///  - io::load_triangle_mesh on the same file throws nothing but InvalidInput naming the file; a
///    mesh it accepts has finite vertices, and fixed probes (a ray from (0, 1000, 0) to
///    (0, -1000, 0), a unit sphere at the origin within 1000) get finite answers when its bounds
///    lie within kFiniteQueryRange (collide/core/finite_range.hpp), and so do its distance
///    fields (check_mesh_fields);
///  - make_walk_mesh on the soup (what `collide walk` does) throws nothing but InvalidInput
///    naming the file;
///  - io::load_hulls_obj (what `collide decompose --hulls` reads) throws nothing but
///    InvalidInput naming the file; its hulls have finite vertices.
/// Crashes, hangs and undefined behaviour are the sanitizers' and the fuzzer's to catch.
inline std::string check_obj_mesh(std::string_view input) {
  // The reader takes a path: one scratch file per process.
  static const std::string path = scratch_path("collide_fuzz_obj", ".obj").string();
  const std::string prefix = std::filesystem::path(path).filename().string() + ":";  // messages start so
  if (!write_file(path, input)) return "cannot write the scratch file " + path;
  TriangleSoup soup;
  try {
    soup = io::load_obj(path);
  } catch (const InvalidInput& e) {
    return check_message(e.what(), prefix);
  } catch (const std::exception& e) {
    return std::string("load_obj threw other than InvalidInput: ") + e.what();
  }
  if (soup.triangles.empty()) return "an accepted soup has no triangles";
  for (const Vec3& p : soup.positions) {
    if (!is_finite(p)) return "an accepted soup holds a position that is not finite";
  }
  for (const glm::uvec3& t : soup.triangles) {
    for (int k = 0; k < 3; ++k) {
      if (t[k] >= soup.positions.size()) return "an accepted soup has a vertex index out of range";
    }
  }

  try {
    const TriangleMesh mesh = io::load_triangle_mesh(path);
    for (const Vec3& v : mesh.vertices) {
      if (!is_finite(v)) return "an accepted mesh holds a vertex that is not finite";
    }
    const RayHit3 hit = raycast(mesh, Transform3{}, Ray3{{0.0f, 1000.0f, 0.0f}, {0.0f, -2000.0f, 0.0f}});
    const DistanceResult3 d = distance(make_sphere({0.0f, 0.0f, 0.0f}, 1.0f), Transform3{}, mesh, Transform3{}, 1000.0f);
    // Finite answers are promised within kFiniteQueryRange; beyond, the queries ran for the
    // sanitizers alone.
    const bool in_range = within_finite_range(compute_aabb(mesh, Transform3{}));
    if (in_range && hit.hit && (!std::isfinite(hit.fraction) || !is_finite(hit.point) || !is_finite(hit.normal))) {
      return "a ray cast on an accepted mesh is not finite";
    }
    if (in_range && d.distance <= 1000.0f && (!std::isfinite(d.distance) || !is_finite(d.point_a) || !is_finite(d.point_b))) {
      return "a distance to an accepted mesh is not finite";
    }
    if (in_range) {
      if (std::string problem = check_mesh_fields(mesh); !problem.empty()) return problem;
    }
  } catch (const InvalidInput& e) {
    if (std::string problem = check_message(e.what(), prefix); !problem.empty()) return problem;
  } catch (const std::exception& e) {
    return std::string("load_triangle_mesh threw other than InvalidInput: ") + e.what();
  }

  try {
    (void)make_walk_mesh(soup);
  } catch (const InvalidInput& e) {
    if (std::string problem = check_message(e.what(), prefix); !problem.empty()) return problem;
  } catch (const std::exception& e) {
    return std::string("make_walk_mesh threw other than InvalidInput: ") + e.what();
  }

  try {
    for (const ConvexHull& hull : io::load_hulls_obj(path)) {
      for (const Vec3& v : hull.vertices) {
        if (!is_finite(v)) return "an accepted hull holds a vertex that is not finite";
      }
    }
  } catch (const InvalidInput& e) {
    if (std::string problem = check_message(e.what(), prefix); !problem.empty()) return problem;
  } catch (const std::exception& e) {
    return std::string("load_hulls_obj threw other than InvalidInput: ") + e.what();
  }
  return {};
}

}  // namespace collide::fuzz
