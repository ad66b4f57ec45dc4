// libFuzzer target: any bytes as an OBJ file, read as a walk-mesh soup, as a collision mesh and
// into a walk mesh; the contract is fuzz/obj_mesh_check.hpp. Build and run: fuzz/run-fuzz
// (docs/fuzzing.md).

#include "fuzz_check.hpp"
#include "obj_mesh_check.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fuzz = collide::fuzz;
  return fuzz::report("fuzz_obj_mesh", fuzz::check_obj_mesh(fuzz::as_text(data, size)));
}
