// OBJ level meshes: the `v` and `f` statements, read and checked in one pass, naming the file
// and line of anything wrong, and faces with more than three corners triangulated in their plane.
//
// The reader is our own: a level needs two statements of the format, and each must be checked
// where general readers are lenient. tinyobjloader (used before issue 15) read "nan", "abc" or a
// missing coordinate as 0 and dropped bad faces with a warning, so every statement was checked
// here first anyway; and it allocated what the file asked for (a `t` tag line of a dozen bytes
// reserves 8192 integers, reals and strings, kept to the end), which a hostile file turns into
// gigabytes.
#include <collide/io/obj.hpp>

#include "text_file.hpp"

#include <collide/core/error.hpp>
#include <collide/decompose/convex_decomposition.hpp>


#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace collide::io {
namespace {

/// One `f` statement: where it is and which of the face corners (ObjReader::corners) it owns.
struct Face {
  std::size_t line;   ///< 1-based line of the file
  std::size_t first;  ///< its first corner in ObjReader::corners
  std::size_t count;  ///< how many corners
};

/// The one pass over the text: positions as read, faces as 0-based vertex indices.
class ObjReader {
 public:
  ObjReader(std::string name, const ObjLimits& limits) : name_(std::move(name)), limits_(limits) {
    limits_.max_vertices = std::min(limits_.max_vertices, kMaxObjVertices);  // limits only tighten
    limits_.max_triangles = std::min(limits_.max_triangles, kMaxObjTriangles);
    limits_.max_face_vertices = std::min(limits_.max_face_vertices, kMaxObjFaceVertices);
  }

  void read(std::string_view text) {
    std::size_t pos = 0;
    while (pos < text.size()) {
      std::string_view s = next_line(text, pos);
      ++line_;
      while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
      if (s.size() < 2 || !is_blank(s[1])) continue;  // only `v` and `f` are used; others are skipped
      if (s[0] == 'v') vertex(s.substr(2));
      if (s[0] == 'f') face(s.substr(2));
    }
    // OBJ lets faces refer to later vertices: the positive references are checked now.
    for (const Face& f : faces_) {
      for (std::size_t k = f.first; k < f.first + f.count; ++k) {
        if (corners_[k] >= positions_.size()) {
          throw InvalidInput(at(f.line) + "face " + std::to_string(&f - faces_.data() + 1) + ": vertex index " +
                             std::to_string(corners_[k] + 1) + " out of range (" + std::to_string(positions_.size()) +
                             " vertices)");
        }
      }
    }
  }

  TriangleSoup triangulate() const {
    TriangleSoup soup;
    soup.name = name_;
    soup.positions = positions_;
    soup.triangles.reserve(triangles_);
    std::vector<Vec3> corners;
    for (std::size_t i = 0; i < faces_.size(); ++i) {
      const Face& f = faces_[i];
      const std::uint32_t* index = corners_.data() + f.first;
      if (f.count == 3) {  // as it is: a degenerate one is build_walk_mesh's to drop and count
        soup.triangles.push_back({index[0], index[1], index[2]});
        continue;
      }
      corners.clear();
      for (std::size_t k = 0; k < f.count; ++k) corners.push_back(positions_[index[k]]);
      const std::string where = name_ + ":" + std::to_string(f.line) + ": face " + std::to_string(i + 1);
      for (const TriangleIndices& t : triangulate_planar_polygon(corners, where)) {
        soup.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
      }
    }
    return soup;
  }

  [[nodiscard]] bool has_faces() const { return !faces_.empty(); }

 private:
  std::string at(std::size_t line) const { return name_ + ":" + std::to_string(line) + ": "; }

  /// "x y z [w]" (or the "x y z r g b" colour extension): x, y, z finite floats; the rest unread.
  void vertex(std::string_view rest) {
    const std::string what = at(line_) + "vertex " + std::to_string(positions_.size() + 1) + ": ";
    if (positions_.size() >= limits_.max_vertices) {
      throw InvalidInput(what + "more vertices than the limit of " + std::to_string(limits_.max_vertices) +
                         " (ObjLimits::max_vertices)");
    }
    float xyz[3];
    for (int k = 0; k < 3; ++k) {
      const std::string_view word = next_word(rest);
      if (word.empty()) throw InvalidInput(what + std::to_string(k) + " coordinates, need 3 (x y z)");
      const std::string coordinate = "coordinate " + std::string(1, "xyz"[k]) + " " + quoted(word);
      switch (parse_float_word(word, xyz[k])) {
        case FloatWord::ok: break;
        case FloatWord::not_finite: throw InvalidInput(what + coordinate + " is not finite");
        case FloatWord::out_of_range: throw InvalidInput(what + coordinate + " is out of float range");
        case FloatWord::not_a_number: throw InvalidInput(what + coordinate + " is not a number");
      }
    }
    positions_.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  /// "v", "v/vt", "v//vn" or "v/vt/vn" per corner: v a non-zero integer, counting from 1, or back
  /// from the latest vertex when negative; vt and vn are not used.
  void face(std::string_view rest) {
    const std::size_t number = faces_.size() + 1;
    const std::string what = at(line_) + "face " + std::to_string(number) + ": ";
    const std::size_t first = corners_.size();
    for (std::string_view word = next_word(rest); !word.empty(); word = next_word(rest)) {
      if (corners_.size() - first == limits_.max_face_vertices) {
        throw InvalidInput(what + "more vertices than the limit of " + std::to_string(limits_.max_face_vertices) +
                           " per face (ObjLimits::max_face_vertices; triangulating is quadratic in them)");
      }
      const std::string_view v = word.substr(0, word.find('/'));
      long long index = 0;
      const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), index);
      if (ec == std::errc::result_out_of_range && ptr == v.data() + v.size()) {
        throw InvalidInput(what + "vertex index " + quoted(v) + " out of range (" + std::to_string(positions_.size()) +
                           " vertices so far)");
      }
      if (ec != std::errc() || ptr != v.data() + v.size() || index == 0) {
        throw InvalidInput(what + "vertex reference " + quoted(word) +
                           " is not a vertex index (a non-zero integer; OBJ counts from 1)");
      }
      const auto so_far = static_cast<long long>(positions_.size());
      if (index < -so_far) {  // (never -index: that overflows for the most negative one)
        throw InvalidInput(what + "vertex index " + std::to_string(index) + " points before the first vertex (" +
                           std::to_string(so_far) + " vertices so far)");
      }
      // A positive one may name a later vertex (checked at the end), but never one past the limit.
      if (index > static_cast<long long>(limits_.max_vertices)) {
        throw InvalidInput(what + "vertex index " + std::to_string(index) + " out of range (more than the limit of " +
                           std::to_string(limits_.max_vertices) + " vertices, ObjLimits::max_vertices)");
      }
      corners_.push_back(static_cast<std::uint32_t>(index > 0 ? index - 1 : so_far + index));
    }
    const std::size_t count = corners_.size() - first;
    if (count < 3) throw InvalidInput(what + std::to_string(count) + " vertices, need at least 3");
    if (count - 2 > limits_.max_triangles - triangles_) {
      throw InvalidInput(what + "the faces make more triangles than the limit of " +
                         std::to_string(limits_.max_triangles) + " (ObjLimits::max_triangles)");
    }
    triangles_ += count - 2;
    faces_.push_back({line_, first, count});
  }

  std::string name_;
  ObjLimits limits_;
  std::size_t line_ = 0;
  std::vector<Vec3> positions_;
  std::vector<std::uint32_t> corners_;  ///< every face's vertex indices, 0-based, in file order
  std::vector<Face> faces_;
  std::size_t triangles_ = 0;  ///< the faces' triangles so far: n - 2 per face of n corners
};

}  // namespace

TriangleSoup load_obj(const std::string& path, const ObjLimits& limits) {
  const std::string name = std::filesystem::path(path).filename().string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InvalidInput(path + ": file not found");
  if (std::filesystem::is_directory(path, ec)) throw InvalidInput(path + ": is a folder, not an OBJ file");
  std::string why;
  const std::optional<std::string> text = io::read_text_file(path, why);
  if (!text) throw InvalidInput(path + ": " + why);
  ObjReader reader(name, limits);
  reader.read(*text);
  if (!reader.has_faces()) throw InvalidInput(name + ": no faces (no 'f' statement)");
  return reader.triangulate();
}

TriangleMesh load_triangle_mesh(const std::string& path, const TriangleMeshOptions& options, const ObjLimits& limits) {
  const TriangleSoup soup = load_obj(path, limits);
  try {
    return make_triangle_mesh(soup.positions, soup.triangles, options);
  } catch (const InvalidInput& e) {
    throw InvalidInput(soup.name + ": " + e.what());
  }
}

std::vector<ConvexHull> load_hulls_obj(const std::string& path, const ObjLimits& limits) {
  const TriangleSoup soup = load_obj(path, limits);
  // Components by shared vertex index: union-find over the triangles' corners (path halving).
  std::vector<std::uint32_t> parent(soup.positions.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<std::uint32_t>(i);
  auto root = [&parent](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const glm::uvec3& t : soup.triangles) {
    for (int k = 1; k < 3; ++k) {
      const std::uint32_t a = root(t[0]), b = root(t[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  // Each component's used vertices, components numbered by their first triangle.
  std::vector<std::int64_t> component_of_root(soup.positions.size(), -1);
  std::vector<std::vector<Vec3>> clouds;
  std::vector<bool> taken(soup.positions.size(), false);
  for (const glm::uvec3& t : soup.triangles) {
    const std::uint32_t r = root(t[0]);
    if (component_of_root[r] < 0) {
      component_of_root[r] = static_cast<std::int64_t>(clouds.size());
      clouds.emplace_back();
    }
    std::vector<Vec3>& cloud = clouds[static_cast<std::size_t>(component_of_root[r])];
    for (int k = 0; k < 3; ++k) {
      if (!taken[t[k]]) {
        taken[t[k]] = true;
        cloud.push_back(soup.positions[t[k]]);
      }
    }
  }
  std::vector<ConvexHull> hulls;
  hulls.reserve(clouds.size());
  for (std::size_t h = 0; h < clouds.size(); ++h) {
    try {
      hulls.push_back(make_convex_hull(clouds[h]));
    } catch (const InvalidInput& e) {
      throw InvalidInput(soup.name + ": hull " + std::to_string(h + 1) + ": " + e.what());
    }
  }
  return hulls;
}

}  // namespace collide::io
