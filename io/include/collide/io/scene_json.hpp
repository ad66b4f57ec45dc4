#pragma once
/// @file
/// Scene JSON: a 2D world written by hand (bounds, statics, bodies, random bodies to spawn, a
/// laser), the input of `collide run FILE.json`. The contract is `docs/scene-json.md`; shapes and
/// transforms use the vocabulary of `collide query` (`spec/query-jsonl.md`).
///
/// Units: world units and seconds; angles in radians, counter-clockwise, y up. The loader turns
/// the file into World2D definitions: every shape validated and built by the make_* functions,
/// concave outlines cut into convex pieces (`convex_pieces`), polylines into one Segment per
/// link. It allocates; load time only.

#include <collide/core/aabb.hpp>
#include <collide/core/ray.hpp>
#include <collide/world/world2d.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace collide {

/// Default wall thickness of a scene, as a fraction of the bounds' smaller side.
inline constexpr float kSceneDefaultWallFraction = 0.02f;
/// A body may start overlapping a solid static by at most this fraction of the bounds' larger
/// side (touching, up to float rounding, is fine; deeper is a scene error).
inline constexpr float kSceneStartOverlapFraction = 1e-4f;
/// Most bodies a scene may ask to spawn (as `collide run --bodies`).
inline constexpr int kSceneMaxSpawn = 1000000;
/// Default share of bullets among spawned bodies: one in this many.
inline constexpr int kSceneBodiesPerBullet = 50;
/// Most convex pieces of one static or body (World2D names pieces with 16 bits).
inline constexpr std::size_t kSceneMaxPieces = 65535;

/// Random bodies to place in the free space of the bounds (the scene's `spawn`). When the file
/// has no `spawn`, `count` is 0 and the other fields hold the defaults (so `--bodies N` can use
/// them). L is the bounds' smaller side.
struct SceneSpawn {
  int count = 0;                 ///< bodies to place, 0..kSceneMaxSpawn
  std::uint32_t seed = 1;        ///< random seed
  float min_radius = 0.0f;       ///< size range of a body, world units (default L/400..L/150)
  float max_radius = 0.0f;
  float min_speed = 0.0f;        ///< speed range, world units per second (default L/60..L/12)
  float max_speed = 0.0f;
  int bullets = 0;               ///< of `count`, small fast bodies (default count / 50)
  float bullet_speed = 0.0f;     ///< world units per second (default 2 L, at most kMaxWorldSpeed)
};

/// A laser cast every frame and reflected by the statics (the scene's `laser`).
struct SceneLaser {
  Ray ray{};                ///< world space; translation non-zero
  float sweep = 0.0f;       ///< radians of phase per frame: at frame f the ray turns by 0.6 sin(sweep f)
};

/// A loaded scene file: World2D definitions and the run's parameters.
struct SceneDescription {
  std::filesystem::path path;      ///< the file (or the name given to parse_scene_json)
  Aabb bounds;                     ///< where bodies belong; min < max
  float wall_thickness = 0.0f;     ///< of the four walls just outside `bounds`; 0: none
  std::vector<StaticDef> statics;  ///< in file order (statics[i] is the file's statics[i])
  std::vector<BodyDef> bodies;     ///< in file order
  SceneSpawn spawn;                ///< count 0 when the file has no `spawn`
  std::optional<SceneLaser> laser;
};

/// Reads the scene JSON file at `path` (see docs/scene-json.md). Throws InvalidInput
/// "FILE: PATH: reason", PATH the JSON path of the bad field ("statics[2].shapes[0].radius"),
/// when the file cannot be read, is not valid JSON (the message gives the line, the column and
/// the path being read), has an unknown or missing field, a value of the wrong type or length, a
/// number that is not a finite float, an unknown shape type, a negative radius, a polygon that is
/// not convex and counter-clockwise (unless marked concave), a self-intersecting or degenerate
/// outline, a value out of range, a body outside the bounds or starting inside a solid static.
/// Never anything else: every other failure is reported as InvalidInput too.
[[nodiscard]] SceneDescription load_scene_json(const std::filesystem::path& path);

/// The same from text already in memory; `name` stands for the file in error messages.
[[nodiscard]] SceneDescription parse_scene_json(std::string_view text, const std::filesystem::path& name);

}  // namespace collide
