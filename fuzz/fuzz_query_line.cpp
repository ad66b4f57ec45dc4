// libFuzzer target: any bytes as one `collide query` line (and as a stream, and as a cast
// question). Build and run: fuzz/run-fuzz (docs/fuzzing.md).

#include "query_line_check.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = collide::fuzz::check_query_line({reinterpret_cast<const char*>(data), size});
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_query_line: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
