// libFuzzer target: any bytes as a scene JSON file, and an accepted scene run for two steps.
// Build and run: fuzz/run-fuzz (docs/fuzzing.md).

#include "scene_json_check.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = collide::fuzz::check_scene_json({reinterpret_cast<const char*>(data), size});
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_scene_json: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
