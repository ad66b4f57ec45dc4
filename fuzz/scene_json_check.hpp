#pragma once
// What must hold for any bytes given to the scene loader as a file (fuzz_scene_json, and the
// regression test that replays the inputs the fuzzer found): shared so both check the same.

#include "fuzz_check.hpp"

#include <collide/core/error.hpp>
#include <collide/io/scene_json.hpp>
#include <collide/world/world2d.hpp>

#include <exception>
#include <string>
#include <string_view>

namespace collide::fuzz {

/// "" when `input` is handled as docs/scene-json.md says, else what went wrong:
///  - parse_scene_json throws nothing but InvalidInput, whose message names the file first and
///    is valid UTF-8;
///  - a scene it accepts can be run: its statics and bodies go into a World2D without an error
///    ("rejected before the first frame" is the loader's promise) and the world steps twice.
///    Spawned bodies are left out (their placement is the run's, not the loader's).
/// Crashes and undefined behaviour are the sanitizers' to catch.
inline std::string check_scene_json(std::string_view input) {
  SceneDescription scene;
  try {
    scene = parse_scene_json(input, "fuzz.json");
  } catch (const InvalidInput& e) {
    return check_message(e.what(), "fuzz.json: ");
  } catch (const std::exception& e) {
    return std::string("parse_scene_json threw other than InvalidInput: ") + e.what();
  }
  try {
    WorldOptions options;
    options.bounds = scene.bounds;
    World2D world(options);
    for (const StaticDef& def : scene.statics) world.add_static(def);
    for (const BodyDef& def : scene.bodies) world.add_body(def);
    world.step(1.0f / 60.0f);
    world.step(1.0f / 60.0f);
  } catch (const std::exception& e) {
    return std::string("a loaded scene cannot be run: ") + e.what();
  }
  return {};
}

}  // namespace collide::fuzz
