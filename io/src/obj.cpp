// OBJ level meshes through tinyobjloader, with the checks it does not make.
//
// tinyobjloader (2.0rc10, Debian) is lenient where a level pipeline must not be: it reads "nan",
// "abc" or a missing coordinate as 0 (a vertex silently moved to the origin), drops faces with
// fewer than three vertices and quads with a bad index with only a warning, and its polygon
// triangulation reads vertex arrays without a bounds check. So before handing the text to it we
// check every `v` and `f` statement ourselves, naming the file and line, and we split polygons
// into triangles ourselves, so that a polygon we cannot split is named by its line.
#include <collide/io/obj.hpp>

#include "text_file.hpp"

#include <collide/core/error.hpp>

#include <tiny_obj_loader.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

namespace collide::io {
namespace {

/// What the strict pass learnt about one `f` statement.
struct FaceLine {
  std::size_t line = 0;      ///< 1-based line of the file
  std::size_t vertices = 0;  ///< how many vertex references it has
};

/// What the strict pass learnt about the whole file.
struct ObjOutline {
  std::size_t vertices = 0;     ///< `v` statements
  std::vector<FaceLine> faces;  ///< `f` statements, in file order
};

bool is_blank(char c) { return c == ' ' || c == '\t'; }

/// The blank-separated words of a statement, after its keyword.
std::vector<std::string_view> words(std::string_view rest) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < rest.size()) {
    while (i < rest.size() && is_blank(rest[i])) ++i;
    const std::size_t start = i;
    while (i < rest.size() && !is_blank(rest[i])) ++i;
    if (i > start) out.push_back(rest.substr(start, i - start));
  }
  return out;
}

/// Checks every `v` and `f` statement (the only ones a walk mesh uses), throwing InvalidInput
/// "FILE:LINE: ..." for: a vertex with fewer than three coordinates, or one of x, y, z that is not
/// a finite float; a face with fewer than three vertices, or a vertex reference that is not a
/// non-zero integer or points outside the vertices (a negative, relative, one before the first;
/// a positive one beyond the last in the file). Lines end at "\n", "\r\n" or "\r", as
/// tinyobjloader reads them; other statements are left to it.
ObjOutline check_statements(const std::string& text, const std::string& name) {
  ObjOutline out;
  struct Reference {
    std::size_t line, face;
    long long index;  // 1-based
  };
  std::vector<Reference> forward;  // positive vertex indices, checked once all vertices are known
  std::size_t line = 0, pos = 0;
  while (pos < text.size()) {
    std::size_t end = pos;
    while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
    std::string_view s(text.data() + pos, end - pos);
    pos = end + (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n' ? 2 : 1);
    ++line;
    while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
    if (s.size() < 2 || !is_blank(s[1]) || (s[0] != 'v' && s[0] != 'f')) continue;
    const std::vector<std::string_view> w = words(s.substr(2));
    const std::string at = name + ":" + std::to_string(line) + ": ";
    if (s[0] == 'v') {
      ++out.vertices;
      const std::string vertex = "vertex " + std::to_string(out.vertices) + ": ";
      if (w.size() < 3) {
        throw InvalidInput(at + vertex + std::to_string(w.size()) + " coordinates, need 3 (x y z)");
      }
      for (int k = 0; k < 3; ++k) {
        std::string_view word = w[static_cast<std::size_t>(k)];
        const std::string quoted = "coordinate " + std::string(1, "xyz"[k]) + " '" + std::string(word) + "'";
        if (word.size() > 1 && word.front() == '+') word.remove_prefix(1);  // from_chars takes no '+'
        // Parsed as double: what underflows float is a valid 0, what overflows it is not.
        double value = 0.0;
        const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
        const bool whole = ptr == word.data() + word.size();
        if (ec == std::errc() && whole && !std::isfinite(value)) throw InvalidInput(at + vertex + quoted + " is not finite");
        if (ec == std::errc::result_out_of_range || std::fabs(value) > std::numeric_limits<float>::max()) {
          throw InvalidInput(at + vertex + quoted + " is out of float range");
        }
        if (ec != std::errc() || !whole) throw InvalidInput(at + vertex + quoted + " is not a number");
      }
      continue;
    }
    const std::size_t face = out.faces.size() + 1;
    const std::string what = "face " + std::to_string(face) + ": ";
    if (w.size() < 3) throw InvalidInput(at + what + std::to_string(w.size()) + " vertices, need at least 3");
    for (const std::string_view word : w) {
      const std::string_view v = word.substr(0, word.find('/'));  // "v", "v/vt", "v//vn", "v/vt/vn"
      long long index = 0;
      const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), index);
      if (ec != std::errc() || ptr != v.data() + v.size() || index == 0) {
        throw InvalidInput(at + what + "vertex reference '" + std::string(word) +
                           "' is not a vertex index (a non-zero integer; OBJ counts from 1)");
      }
      if (index < 0 && -index > static_cast<long long>(out.vertices)) {
        throw InvalidInput(at + what + "vertex index " + std::to_string(index) + " points before the first vertex (" +
                           std::to_string(out.vertices) + " vertices so far)");
      }
      if (index > 0) forward.push_back({line, face, index});
    }
    out.faces.push_back({line, w.size()});
  }
  for (const Reference& r : forward) {  // OBJ lets faces refer to later vertices
    if (r.index > static_cast<long long>(out.vertices)) {
      throw InvalidInput(name + ":" + std::to_string(r.line) + ": face " + std::to_string(r.face) + ": vertex index " +
                         std::to_string(r.index) + " out of range (" + std::to_string(out.vertices) + " vertices)");
    }
  }
  return out;
}

/// Splits one polygon into triangles: a fan from its first corner, wound as the polygon. A quad
/// takes whichever diagonal keeps both triangles wound like the polygon (its Newell normal); a
/// polygon that no fan covers (non-convex beyond one reflex corner of a quad, or
/// self-intersecting) is rejected: triangulate it in the exporter. Degenerate pieces (no area)
/// pass: build_walk_mesh drops and counts them.
void triangulate(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& face,
                 std::vector<glm::uvec3>& out, const std::string& at) {
  const std::size_t n = face.size();
  if (n == 3) {
    out.push_back({face[0], face[1], face[2]});
    return;
  }
  glm::dvec3 newell(0.0);
  const glm::dvec3 origin(positions[face[0]]);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 a = glm::dvec3(positions[face[i]]) - origin;
    const glm::dvec3 b = glm::dvec3(positions[face[(i + 1) % n]]) - origin;
    newell += glm::cross(a, b);
  }
  auto folds = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {  // wound against the polygon
    const glm::dvec3 pa(positions[a]);
    const glm::dvec3 t = glm::cross(glm::dvec3(positions[b]) - pa, glm::dvec3(positions[c]) - pa);
    return glm::dot(t, newell) < -1e-9 * glm::length(t) * glm::length(newell);
  };
  for (std::size_t first = 0; first < (n == 4 ? 2u : 1u); ++first) {  // a quad may use either diagonal
    bool ok = true;
    for (std::size_t i = 1; i + 1 < n && ok; ++i) {
      ok = !folds(face[first], face[(first + i) % n], face[(first + i + 1) % n]);
    }
    if (!ok) continue;
    for (std::size_t i = 1; i + 1 < n; ++i) out.push_back({face[first], face[(first + i) % n], face[(first + i + 1) % n]});
    return;
  }
  throw InvalidInput(at + "face with " + std::to_string(n) +
                     " vertices is not convex (no fan of triangles covers it); triangulate it when exporting");
}

}  // namespace

TriangleSoup load_obj(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  if (!std::filesystem::exists(path)) throw InvalidInput(path + ": file not found");
  std::string why;
  const std::optional<std::string> read = io::read_text_file(path, why);
  if (!read) throw InvalidInput(path + ": " + why);
  const std::string& text = *read;
  const ObjOutline outline = check_statements(text, name);
  if (outline.faces.empty()) throw InvalidInput(name + ": no faces (no 'f' statement)");

  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // triangulate() below, which names a polygon's line
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(text, "", config)) {
    throw InvalidInput(name + ": cannot parse OBJ: " + reader.Error());
  }
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const std::size_t nv = attrib.vertices.size() / 3;
  TriangleSoup soup;
  soup.name = name;
  soup.positions.reserve(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    soup.positions.push_back({attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]});
  }
  // tinyobjloader keeps the faces in file order (across groups, objects and materials): the k-th
  // face it returns is the k-th `f` statement. Should a future version disagree, say so rather
  // than name wrong lines.
  std::size_t face_count = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) face_count += shape.mesh.num_face_vertices.size();
  if (nv != outline.vertices || face_count != outline.faces.size()) {
    throw InvalidInput(name + ": tinyobjloader read " + std::to_string(nv) + " vertices and " +
                       std::to_string(face_count) + " faces where the file has " + std::to_string(outline.vertices) +
                       " and " + std::to_string(outline.faces.size()));
  }
  std::size_t k = 0;
  std::vector<std::uint32_t> face;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    std::size_t next = 0;
    for (const unsigned int count : shape.mesh.num_face_vertices) {
      const FaceLine& source = outline.faces[k++];
      const std::string at = name + ":" + std::to_string(source.line) + ": ";
      if (count != source.vertices) throw InvalidInput(at + "tinyobjloader read this face differently");
      face.clear();
      for (std::size_t j = 0; j < count; ++j) {
        const int v = shape.mesh.indices[next++].vertex_index;
        if (v < 0 || static_cast<std::size_t>(v) >= nv) {  // checked above; kept as a guard
          throw InvalidInput(at + "vertex index out of range (" + std::to_string(nv) + " vertices)");
        }
        face.push_back(static_cast<std::uint32_t>(v));
      }
      triangulate(soup.positions, face, soup.triangles, at);
    }
  }
  return soup;
}

TriangleMesh load_triangle_mesh(const std::string& path, const TriangleMeshOptions& options) {
  const TriangleSoup soup = load_obj(path);
  try {
    return make_triangle_mesh(soup.positions, soup.triangles, options);
  } catch (const InvalidInput& e) {
    throw InvalidInput(soup.name + ": " + e.what());
  }
}

}  // namespace collide::io
