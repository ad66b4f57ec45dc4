// libFuzzer target: any bytes as a scene JSON file, and an accepted scene run for two steps.
// Build and run: fuzz/run-fuzz (docs/fuzzing.md).

#include "fuzz_check.hpp"
#include "scene_json_check.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fuzz = collide::fuzz;
  return fuzz::report("fuzz_scene_json", fuzz::check_scene_json(fuzz::as_text(data, size)));
}
