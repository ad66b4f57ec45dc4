// libFuzzer target: any bytes as an OBJ file, read as a walk-mesh soup and as a collision mesh
// (io::load_obj, io::load_triangle_mesh). The contract: InvalidInput naming the file, or a mesh
// whose every query-relevant number is finite; nothing else thrown, no crash, no unbounded
// allocation. Build and run: fuzz/run-fuzz (docs/fuzzing.md).

#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <unistd.h>

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz_obj_mesh: %s\n", what.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The reader takes a path: one scratch file per fuzzing process.
  static const std::string path = "/tmp/fuzz_obj_mesh." + std::to_string(::getpid()) + ".obj";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const collide::TriangleMesh mesh = collide::io::load_triangle_mesh(path);
    for (const collide::Vec3& v : mesh.vertices) {
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
        fail("an accepted mesh holds a vertex that is not finite");
      }
    }
    if (mesh.triangles.empty()) fail("an accepted mesh has no triangles");
  } catch (const collide::InvalidInput& e) {
    if (std::string(e.what()).find(path) == std::string::npos) {
      fail(std::string("error does not name the file: ") + e.what());
    }
  }
  return 0;
}
