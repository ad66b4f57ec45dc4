#include <collide/io/obj.hpp>

#include <collide/core/error.hpp>

#include <tiny_obj_loader.h>

#include <filesystem>

namespace collide::io {

TriangleSoup load_obj(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  config.mtl_search_path = "";
  tinyobj::ObjReader reader;
  if (!std::filesystem::exists(path)) throw InvalidInput(path + ": file not found");
  if (!reader.ParseFromFile(path, config)) {
    throw InvalidInput(path + ": cannot parse OBJ: " + reader.Error());
  }
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  TriangleSoup soup;
  soup.name = name;
  const std::size_t nv = attrib.vertices.size() / 3;
  soup.positions.reserve(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const Vec3 p{attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]};
    if (!is_finite(p)) throw InvalidInput(name + ": vertex " + std::to_string(i) + " is not finite");
    soup.positions.push_back(p);
  }
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const auto& indices = shape.mesh.indices;
    for (std::size_t f = 0; f + 2 < indices.size(); f += 3) {
      glm::uvec3 t;
      for (int k = 0; k < 3; ++k) {
        const int v = indices[f + static_cast<std::size_t>(k)].vertex_index;
        if (v < 0 || static_cast<std::size_t>(v) >= nv) {
          throw InvalidInput(name + ": triangle " + std::to_string(soup.triangles.size()) +
                             ": vertex index " + std::to_string(v) + " out of range");
        }
        t[k] = static_cast<unsigned>(v);
      }
      soup.triangles.push_back(t);
    }
  }
  if (soup.triangles.empty()) throw InvalidInput(name + ": no faces");
  return soup;
}

}  // namespace collide::io
