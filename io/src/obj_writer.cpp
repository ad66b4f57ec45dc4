// Convex hulls as an OBJ file: one `o` object per hull, its vertices and its polygonal faces.
//
// Written with stdio: a stream's formatting state and exceptions buy nothing for three
// statements, and errno says why an open or a write failed.
#include <collide/io/obj.hpp>

#include <collide/core/error.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

namespace collide::io {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const noexcept { std::fclose(f); }
};

[[noreturn]] void cannot_write(const std::string& path, int error) {
  throw InvalidInput(path + ": cannot be written (" + (error != 0 ? std::strerror(error) : "write error") + ")");
}

/// Digits that make every float read back as itself (FLT_DECIMAL_DIG).
constexpr int kFloatDigits = 9;

}  // namespace

void write_hulls_obj(const std::string& path, std::span<const ConvexHull> hulls) {
  errno = 0;
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) cannot_write(path, errno);
  std::FILE* f = file.get();
  std::fprintf(f, "# %zu convex hull%s, written by collide\n", hulls.size(), hulls.size() == 1 ? "" : "s");
  std::size_t base = 1;  // OBJ index of the current hull's vertex 0
  for (std::size_t h = 0; h < hulls.size(); ++h) {
    const ConvexHull& hull = hulls[h];
    std::fprintf(f, "o hull_%zu\n", h + 1);
    for (const Vec3& v : hull.vertices) {
      std::fprintf(f, "v %.*g %.*g %.*g\n", kFloatDigits, static_cast<double>(v.x), kFloatDigits,
                   static_cast<double>(v.y), kFloatDigits, static_cast<double>(v.z));
    }
    for (const HullFace& face : hull.faces) {
      std::fputc('f', f);
      for (int k = 0; k < face.count; ++k) std::fprintf(f, " %zu", base + hull.face_vertices[face.first + k]);
      std::fputc('\n', f);
    }
    base += hull.vertices.size();
  }
  errno = 0;
  const bool failed = std::fflush(f) != 0 || std::ferror(f) != 0;
  const int error = errno;
  if (std::fclose(file.release()) != 0 || failed) cannot_write(path, failed ? error : errno);
}

}  // namespace collide::io
