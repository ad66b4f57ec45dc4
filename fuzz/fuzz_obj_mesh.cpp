// libFuzzer target: any bytes as an OBJ file, read as a walk-mesh soup, as a collision mesh and
// into a walk mesh; the contract is fuzz/obj_mesh_check.hpp. Build and run: fuzz/run-fuzz
// (docs/fuzzing.md).

#include "obj_mesh_check.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = collide::fuzz::check_obj_mesh({reinterpret_cast<const char*>(data), size});
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_obj_mesh: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
