// libFuzzer target: any bytes as a points file ("x y" or "x y z" per line, `collide sdf
// --sample`), read as 2D and as 3D points; the contract is fuzz/points_text_check.hpp. Build and
// run: fuzz/run-fuzz (docs/fuzzing.md).

#include "fuzz_check.hpp"
#include "points_text_check.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fuzz = collide::fuzz;
  return fuzz::report("fuzz_points_text", fuzz::check_points_text(fuzz::as_text(data, size)));
}
