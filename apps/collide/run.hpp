#pragma once
// `collide run`: scenes (the embedded default scene, a Tiled map, a scene JSON file) built into a
// World2D, and the frame loop that steps it, casts the laser, writes events and reports. The
// command in run_command.cpp is a thin CLI11 shell over `run_world`, so tests drive the same code.

#include <collide/io/tiled.hpp>
#include <collide/world/world2d.hpp>

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace collide::cli {

/// The laser sweeps this far either side of its first direction (radians).
inline constexpr float kLaserSweepRadians = 0.6f;

/// What `collide run` does; see `collide run --help` for each option.
struct RunOptions {
  /// A Tiled map (.tmx, .tmj, or .json with a "type"), a scene JSON file (any other .json,
  /// docs/scene-json.md) or the name of an embedded scene ("default", "bullets"); empty: "default".
  std::string input;
  int bodies = -1;          ///< bodies to spawn; -1: the scene's own count
  std::uint32_t seed = 1;
  /// The seed was given (--seed): it overrides a scene file's own `spawn.seed`.
  bool seed_given = false;
  int frames = 600;
  float dt = 1.0f / 60.0f;  ///< seconds per frame
  WorldBroadPhase broad_phase = WorldBroadPhase::temporal;
  bool adaptive_early_out = true;
  std::string events;       ///< JSON Lines of contact events; empty: none
  std::string png;          ///< picture of the last frame; empty: none
  std::string svg;
  int picture_width = 1400;
  bool progress = true;     ///< progress bar on stderr when it is a terminal
  /// Tiled maps: the tile and object layers that collide (TiledLoadOptions::layers); empty: the
  /// map's own declarations decide. Refused for other scenes.
  std::vector<std::string> layers;
};

/// A scene built into a world, ready to run.
struct Scene {
  std::string name;          ///< "default scene", or the map's or scene file's path
  World2D world;
  Aabb bounds;               ///< where bodies belong (inside the boundary walls)
  bool y_up = true;          ///< false for Tiled maps (y down, as the map's editor shows them)
  int requested_bodies = 0;  ///< bodies asked for
  int bullets = 0;           ///< of which fast bullets
  std::uint32_t seed = 1;    ///< the seed the scene was built with
  bool has_laser = true;     ///< false: no laser is cast (a scene file without one)
  Ray laser{};               ///< the laser's first pose (it turns as the frames go by)
  /// Radians of phase per frame: at frame f the laser turns by kLaserSweepRadians sin(laser_turn f).
  float laser_turn = 0.0f;
  /// Tiled maps: every layer, whether it collides and why (empty for other scenes).
  std::vector<TiledLayer> map_layers;
};

/// Builds the scene `options` name: throws InvalidInput naming the file (and the element or
/// JSON path) for a map or scene file that cannot be loaded (a directory, a FIFO, a device or an
/// empty file is named before it is opened), listing the embedded scenes for an unknown name,
/// or listing the map's layers for a name in `options.layers` that it does not have.
[[nodiscard]] Scene make_scene(const RunOptions& options);

/// What a run measured.
struct RunReport {
  std::string scene;
  int bodies = 0;
  int statics = 0;
  int static_pieces = 0;
  int split_statics = 0;    ///< statics of several convex pieces (concave outlines, polylines, tiles)
  int frames = 0;
  StepStats total;          ///< summed over the frames
  double wall_seconds = 0.0;
  std::int64_t laser_hits = 0;    ///< summed over the frames
  int laser_last_segments = 0;
  std::uint64_t state_hash = 0;
  std::int64_t events_written = 0;
};

/// Runs `options`: builds the scene, steps it `frames` times with the laser cast each frame,
/// writes events and pictures when asked, and prints the summary to `out` (none when null).
/// Throws InvalidInput for bad options or input files (naming them).
RunReport run_world(const RunOptions& options, std::FILE* out);

}  // namespace collide::cli
