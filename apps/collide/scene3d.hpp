#pragma once
// The 3D scene `collide run` steps (an OBJ level, or the embedded 3D scene with --3d), built
// into a World3D: shared by run3d.cpp and the benchmarks that step the same scene.

#include "run.hpp"

#include <collide/world/character.hpp>
#include <collide/world/world3d.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace collide::cli {

/// A character walking the level with move_character (a capsule standing along y).
struct Character {
  Shape3D shape;
  Transform3 xf;
  Vec3 velocity{0.0f};
  float heading = 0.0f;     ///< walking direction about y, radians
  std::vector<Vec3> trail;  ///< recent positions, oldest first (the picture's paths)
  bool grounded = false;    ///< the last move ended on the ground
  std::optional<CharacterMove3> last;  ///< the last move (the next one reuses its ground probe)
};

/// A 3D scene built into a world, ready to run.
struct Scene3D {
  std::string name;
  std::shared_ptr<TaskScheduler> scheduler;  ///< the step's job system; the world points to it
  World3D world;
  Aabb3 level;                  ///< the level's box (statics), world units, y up
  Aabb3 spawn;                  ///< where bodies are spawned
  bool closed = false;          ///< the embedded scene: bodies must stay in `level` (escaped)
  float body_size = 0.5f;       ///< about a body's bounding radius, world units
  int requested_bodies = 0;
  int bullets = 0;
  std::vector<Character> characters;
  int requested_characters = 0;
  float character_height = 1.8f;
  Ray3 laser{};
  std::uint32_t seed = 1;
};

/// Builds the 3D scene `options` asks for: the OBJ level `options.input` (its triangles one
/// static mesh) or, with no input, the embedded 3D scene (rooms of 40 x 12 x 40 with a height-
/// field floor, ramps, stairs, rocks, pillars and thin walls; as many rooms as `options.bodies`
/// needs at `options.density`); bodies spawned in free space (RunOptions::seed), characters on
/// walkable floor. Throws InvalidInput naming the file or option that cannot be used.
[[nodiscard]] Scene3D make_scene3d(const RunOptions& options);

}  // namespace collide::cli
