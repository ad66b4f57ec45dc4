// libFuzzer target: any bytes as one `collide query` line (and as a stream, and as a cast
// question). Build and run: fuzz/run-fuzz (docs/fuzzing.md).

#include "fuzz_check.hpp"
#include "query_line_check.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fuzz = collide::fuzz;
  return fuzz::report("fuzz_query_line", fuzz::check_query_line(fuzz::as_text(data, size)));
}
