// libFuzzer target: the shape constructors (2D and 3D) on numbers decoded from the fuzz bytes,
// NaN, infinities, huge and denormal values included, and every built shape queried against
// fixed probes; the contract is fuzz/shapes_check.hpp. Build and run: fuzz/run-fuzz
// (docs/fuzzing.md).

#include "fuzz_check.hpp"
#include "shapes_check.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fuzz = collide::fuzz;
  return fuzz::report("fuzz_shapes", fuzz::check_shapes(fuzz::as_text(data, size)));
}
