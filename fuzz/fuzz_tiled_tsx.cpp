// libFuzzer target: any bytes as the external tileset (.tsx, or .tsj when it starts with '{') of a fixed map,
// through load_tiled_map and the checks of fuzz/tiled_check.hpp. Build and run: fuzz/run-fuzz
// (docs/fuzzing.md).

#include "tiled_check.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // load_tiled_map reads files: one scratch folder per fuzzing process.
  static const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("fuzz_tiled_tsx." + std::to_string(::getpid()));
  const std::string problem =
      collide::fuzz::check_tiled(collide::fuzz::TiledInput::tileset, {reinterpret_cast<const char*>(data), size}, dir);
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_tiled_tsx: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
