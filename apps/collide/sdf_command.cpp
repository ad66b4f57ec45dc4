// `collide sdf FILE`: the CLI11 shell over run_sdf (sdf.hpp).

#include "command_errors.hpp"
#include "commands.hpp"
#include "sdf.hpp"

#include <collide/draw/picture.hpp>

#include <cstdio>
#include <memory>
#include <string>

namespace collide::cli {
namespace {

/// Largest --check-points, --particles and --frames: far beyond any use, small enough that the
/// counts stay in int.
constexpr int kMaxSdfCount = 100000000;
/// Largest --margin, voxels.
constexpr int kMaxSdfMargin = 1 << 20;

}  // namespace

void register_sdf_command(CLI::App& app) {
  auto options = std::make_shared<SdfOptions>();
  auto max_memory = std::make_shared<std::string>("2G");
  CLI::App* cmd = app.add_subcommand(
      "sdf", "Build the signed distance field of a map, a scene or a mesh; measure, draw, sample it");
  cmd->add_option("FILE", options->input,
                  "A Tiled map (.tmx, .tmj, .json with a \"type\"): its colliders, map pixels, y down; a scene "
                  "JSON file (.json): its statics but sensors (not the walls `collide run` adds); or an OBJ "
                  "mesh (.obj): 3D, signed by its winding number")
      ->required();
  cmd->add_option("--voxel", options->voxel,
                  "Node spacing, world units (default: the input's bounds' largest side / 256)")
      ->check(CLI::PositiveNumber);
  CLI::Option* band = cmd->add_option("--band", options->band,
                                      "Build the sparse narrow-band field, nothing stored beyond this many "
                                      "voxels from the surface (default: the dense field, exact within 3)")
                          ->check(CLI::PositiveNumber);
  cmd->add_option("--margin", options->margin, "Nodes beyond the input's bounds on each side, voxels")
      ->capture_default_str()->check(CLI::Range(1, kMaxSdfMargin));
  cmd->add_option("--max-memory", *max_memory,
                  "Refuse a field that would need more: bytes, or with K, M, G, T (powers of 1024)")
      ->capture_default_str();
  cmd->add_option("--layers", options->layers, "Tiled maps: the layers that collide (as `collide run --layers`)");
  cmd->add_option("--check-points", options->check_points,
                  "Random points of the grid's box the error against exact distances is measured on")
      ->capture_default_str()->check(CLI::Range(0, kMaxSdfCount));
  cmd->add_option("--seed", options->seed, "Random seed of the check points and the particles")->capture_default_str();
  cmd->add_option("--png", options->png,
                  "Write the field as a picture: colour-mapped (inside blue, outside orange), iso-lines, the "
                  "zero contour; 2D the whole field, 3D a slice");
  cmd->add_option("--png-size", options->png_size, "The picture's plot, longer side, pixels")
      ->capture_default_str()->check(CLI::Range(16, kMaxPictureSide));
  cmd->add_option("--slice", options->slice,
                  "3D: the plane drawn, AXIS=VALUE in world units (y=1.5: seen from above, x right, z down; "
                  "default y at the middle of the grid)");
  cmd->add_option("--particles", options->particles,
                  "Bounce this many particles off the field (spawned in free space, at most a voxel per step) "
                  "and report the time per particle step")
      ->capture_default_str()->check(CLI::Range(0, kMaxSdfCount));
  cmd->add_option("--frames", options->frames, "Particle steps")->capture_default_str()->check(CLI::Range(0, kMaxSdfCount));
  cmd->add_option("--dt", options->dt, "Seconds per particle step")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--gravity", options->gravity,
                  "Particles' gravity, world units per second squared, down as the input shows it (+y in a "
                  "Tiled map, -y otherwise)")
      ->capture_default_str();
  cmd->add_option("--restitution", options->restitution, "Particles' bounce: 0 stick, 1 elastic")
      ->capture_default_str()->check(CLI::Range(0.0f, 1.0f));
  cmd->add_option("--sample", options->sample,
                  "A points file (\"x y\" or \"x y z\" per line, world units; blank lines and # comments "
                  "skipped): print the field's value at each, one per line, in order. Standard output then "
                  "holds those values alone; the report goes to standard error");
  cmd->footer(
      "Prints the build (time, memory, nodes, band nodes) and the field's error against exact distances on "
      "random points of the grid's box: 2D the nearest shape's distance (on the points outside every shape; "
      "those inside one are checked for sign), 3D the mesh's nearest triangle signed by the winding number; a "
      "sparse field against the exact distance clamped to its band.\n"
      "Examples:\n"
      "  collide sdf ../shared/data/tiled/melonjs/platformer/map/map1.tmx --png map1_sdf.png\n"
      "  collide sdf ../shared/data/meshes/recast/dungeon.obj --voxel 0.25 --band 3 --particles 10000\n"
      "  collide sdf level.json --sample points.txt > distances.txt");
  cmd->callback([options, max_memory, band]() {
    const int code = run_guarded("sdf", options->input, [&] {
      options->max_bytes = parse_byte_size(*max_memory, "--max-memory");
      options->sparse = band->count() > 0;
      const bool sampling = !options->sample.empty();
      return run_sdf(*options, sampling ? stderr : stdout, stdout);
    });
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace collide::cli
