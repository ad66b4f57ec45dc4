#pragma once
// `collide run`: scenes (the embedded default scene, a Tiled map, a scene JSON file) built into a
// World2D, and the frame loop that steps it, casts the laser, writes events and reports. The
// command in run_command.cpp is a thin CLI11 shell over `run_world`, so tests drive the same code.

#include <collide/io/tiled.hpp>
#include <collide/world/world2d.hpp>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace collide::cli {

/// Most bodies `collide run --bodies` asks for (about 1.7 KB a body in 2D: a million is 1.7 GB);
/// the embedded scenes reserve room for at most this many up front.
inline constexpr int kMaxRunBodies = 1000000;

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
  /// 3D (an OBJ level, or --3d for the embedded 3D scene): characters walking the floors with
  /// move_character; -1: the scene's own count.
  int characters = -1;
  /// The embedded 3D scene (--3d) when no input is given.
  bool three_d = false;
  /// 3D: the bodies' gravity, world units per second squared along -y (0: none).
  float gravity = 0.0f;
  /// 3D: the camera of --png, "AZIMUTH,ELEVATION[,ZOOM]" in degrees or a name (iso, top,
  /// front, side); empty: iso.
  std::string view;
  /// Worker threads of the step (oneTBB); 0: every core.
  int threads = 0;
  /// The embedded default scene: bodies per unit area relative to its own (3000 bodies in a
  /// 320 x 180 arena); the world grows with --bodies at this density.
  float density = 1.0f;
};

/// A scene built into a world, ready to run.
struct Scene {
  std::string name;          ///< "default scene", or the map's or scene file's path
  /// The step's job system (oneTBB, RunOptions::threads workers); the world points to it.
  std::shared_ptr<TaskScheduler> scheduler;
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

/// What a scene file is, as `collide run` (and `collide sdf`) tell it.
enum class SceneFileKind : unsigned char {
  tiled_map,   ///< .tmx, .tmj, or .json with a "type" member (looks_like_tiled_json)
  scene_json,  ///< any other .json (docs/scene-json.md)
  other,       ///< neither (an embedded scene's name, an OBJ level, ...)
};

/// The kind of the file `path` names, by its extension and, for .json, its content. A .tmx,
/// .tmj or .json file is checked first (require_input_file: InvalidInput naming it when it is
/// missing, not a regular file or empty).
[[nodiscard]] SceneFileKind scene_file_kind(const std::string& path);

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
  double setup_seconds = 0.0;     ///< building the scene and spawning its bodies
  int threads = 1;                ///< workers of the step
  std::int64_t laser_hits = 0;    ///< summed over the frames
  int laser_last_segments = 0;
  std::uint64_t state_hash = 0;
  std::int64_t events_written = 0;
  /// 3D: character moves that ended inside static geometry (the check; must be 0).
  std::int64_t characters_inside = 0;
};

/// Runs `options`: builds the scene, steps it `frames` times with the laser cast each frame,
/// writes events and pictures when asked, and prints the summary to `out` (none when null).
/// Throws InvalidInput for bad options or input files (naming them). A 3D input (an OBJ level,
/// or --3d) goes to run_world3d.
RunReport run_world(const RunOptions& options, std::FILE* out);

/// True when `options` asks for a 3D run: --3d, or an .obj input.
[[nodiscard]] bool is_3d_run(const RunOptions& options);

/// The characters' numbers of a 3D run.
struct CharacterReport {
  int characters = 0;
  std::int64_t moves = 0;          ///< move_character calls (characters x frames)
  std::int64_t blocked = 0;        ///< moves cut short
  std::int64_t airborne = 0;       ///< moves ending off the ground
  std::int64_t steps = 0;          ///< moves that climbed a step
  std::int64_t pushed_out = 0;     ///< moves that started inside geometry (a body pushed it)
  float max_penetration = 0.0f;    ///< deepest overlap with a static after any move (the check)
  std::int64_t inside = 0;         ///< moves ending deeper than the tunnelling tolerance: must be 0
  double seconds = 0.0;            ///< time in move_character
};

/// Runs a 3D scene: the level (an OBJ file, y up: its triangles one static mesh) or the
/// embedded 3D scene, bodies spawned in its free space (some of them bullets), characters
/// wandering its floors, a laser with reflections; the same options, checks and summary as the
/// 2D run, plus the characters' numbers. `characters` receives them when not null.
RunReport run_world3d(const RunOptions& options, std::FILE* out, CharacterReport* characters = nullptr);

}  // namespace collide::cli
