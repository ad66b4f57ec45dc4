// libFuzzer target: the shape constructors (2D and 3D) on numbers decoded from the fuzz bytes,
// NaN, infinities, huge and denormal values included, and every built shape queried against
// fixed probes; the contract is fuzz/shapes_check.hpp. Build and run: fuzz/run-fuzz
// (docs/fuzzing.md).

#include "shapes_check.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = collide::fuzz::check_shapes({reinterpret_cast<const char*>(data), size});
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_shapes: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
