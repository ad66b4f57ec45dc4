// libFuzzer target: any bytes as the external tileset (.tsx, or .tsj when it starts with '{') of a fixed map,
// through load_tiled_map and the checks of fuzz/tiled_check.hpp. Build and run: fuzz/run-fuzz
// (docs/fuzzing.md).

#include "fuzz_check.hpp"
#include "tiled_check.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fuzz = collide::fuzz;
  // load_tiled_map reads files: one scratch folder per fuzzing process.
  static const std::filesystem::path dir = fuzz::scratch_path("fuzz_tiled_tsx");
  return fuzz::report("fuzz_tiled_tsx", fuzz::check_tiled(fuzz::TiledInput::tileset, fuzz::as_text(data, size), dir));
}
