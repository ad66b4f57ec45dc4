#pragma once
// `collide sdf FILE`: the signed distance field of a Tiled map, a scene JSON file or an OBJ mesh
// (sdf/distance_field.hpp), built, measured against exact distances, drawn, sampled at given
// points, and bounced particles off. The command in sdf_command.cpp is a thin CLI11 shell over
// `run_sdf`.

#include <collide/sdf/distance_field.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace collide::cli {

/// The default voxel is the input's bounds' largest side divided by this.
inline constexpr float kSdfDefaultVoxelsPerSide = 256.0f;
/// Random points the field's error is measured on, by default.
inline constexpr int kSdfDefaultCheckPoints = 1000;

/// What `collide sdf` does; see `collide sdf --help` for each option.
struct SdfOptions {
  /// A Tiled map (.tmx, .tmj, or .json with a "type"), a scene JSON file (any other .json) or an
  /// OBJ mesh (.obj).
  std::string input;
  float voxel = 0.0f;                       ///< node spacing, world units; 0: the default
  bool sparse = false;                      ///< --band given: the sparse narrow-band field
  float band = kFieldDefaultBand;           ///< exact band, voxels
  int margin = kFieldDefaultMargin;         ///< nodes beyond the input's bounds, voxels
  std::size_t max_bytes = kFieldDefaultMaxBytes;  ///< --max-memory, bytes
  std::vector<std::string> layers;          ///< Tiled maps: the layers that collide (as `collide run`)
  int check_points = kSdfDefaultCheckPoints;  ///< random points of the error measurement
  std::uint32_t seed = 1;                   ///< of the check points and the particles
  std::string png;                          ///< the picture; empty: none
  int png_size = 1024;                      ///< the plot's longer side, pixels
  std::string slice;                        ///< 3D: "AXIS=VALUE" of the picture; empty: y at the middle
  int particles = 0;                        ///< particles to bounce; 0: none
  int frames = 100;                         ///< particle steps
  float dt = 1.0f / 60.0f;                  ///< seconds per particle step
  float gravity = 0.0f;                     ///< world units per second squared, down (see --help)
  float restitution = 0.5f;                 ///< of the particles' bounces, [0, 1]
  std::string sample;                       ///< points file; empty: none
};

/// The geometry a field is built from: 2D shapes (a map's or a scene's solid statics) or a 3D
/// triangle mesh (an OBJ file).
struct SdfInput {
  std::string name;                  ///< the file as given
  int dimension = 2;                 ///< 2 or 3
  bool y_down = false;               ///< a Tiled map: y points down (map pixels)
  std::string unit = "units";        ///< "px" for Tiled maps
  std::vector<PlacedShape> shapes;   ///< 2D: every convex piece, placed
  TriangleMesh mesh;                 ///< 3D
};

/// Loads `options.input` with the loaders `collide run` uses (scene_file_kind, load_tiled_map,
/// load_scene_json, io::load_triangle_mesh): a map's colliders, a scene's statics without its
/// sensors (they push nothing) and without the walls `collide run` puts around a scene's bounds,
/// or an OBJ file's triangles. Throws InvalidInput naming the file, also for another kind of
/// file and for an input without solid geometry.
[[nodiscard]] SdfInput load_sdf_input(const SdfOptions& options);

/// `text` as a number of bytes: digits, optionally a fraction, optionally followed by K, M, G or
/// T (powers of 1024, either case, optionally followed by "B" or "iB"): "2147483648", "512M",
/// "2G", "1.5GiB". Throws InvalidInput naming `option` for anything else, for 0 and for a size
/// beyond std::size_t.
[[nodiscard]] std::size_t parse_byte_size(const std::string& text, const std::string& option);

/// Runs `collide sdf`: loads the input, builds the field (dense, or sparse with --band), and
/// reports to `report` the build (time, memory, nodes, band nodes) and its error against exact
/// distances on seeded random points of the grid's box; then writes the picture (--png),
/// bounces particles (--particles) and prints the field at each point of --sample to `values`,
/// one per line (nothing else goes there). Returns the exit status (0). Throws InvalidInput naming
/// the file or the option for anything wrong, before the build where it can be known then.
int run_sdf(const SdfOptions& options, std::FILE* report, std::FILE* values);

}  // namespace collide::cli
