// Scene JSON (docs/scene-json.md) -> World2D definitions. Every value is checked before use and
// every rejection names the file and the JSON path of the field; the library's own validation
// (make_*, convex_pieces) runs inside `build`, which adds the path to its message.

#include <collide/io/scene_json.hpp>

#include "json_syntax.hpp"
#include "text_file.hpp"

#include <collide/core/error.hpp>
#include <collide/narrow/contact.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace collide {
namespace {

using Json = nlohmann::json;

/// Default spawn sizes and speeds, as fractions of the bounds' smaller side L (docs/scene-json.md).
constexpr float kSpawnMinRadiusFraction = 1.0f / 400.0f;
constexpr float kSpawnMaxRadiusFraction = 1.0f / 150.0f;
constexpr float kSpawnMinSpeedFraction = 1.0f / 60.0f;
constexpr float kSpawnMaxSpeedFraction = 1.0f / 12.0f;
constexpr float kSpawnBulletSpeedFraction = 2.0f;
/// A spawned body's largest size must stay below this fraction of L (it needs room to fit).
constexpr float kSpawnMaxRadiusLimit = 0.25f;

std::string member(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string element(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

/// A value as JSON prints it back (1e39 -> 1e+39), for messages.
std::string shown(const Json& j) { return j.dump(); }

/// Reads one file; knows its name for every error.
class SceneReader {
 public:
  explicit SceneReader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& why) const {
    throw InvalidInput(file_ + ": " + (path.empty() ? std::string("root") : path) + ": " + why);
  }

  /// Runs a library constructor, turning its InvalidInput into an error naming the field.
  template <class F>
  auto build(const std::string& path, F&& make) const {
    try {
      return make();
    } catch (const InvalidInput& e) {
      fail(path, e.what());
    }
  }

  /// Rejects any member of `obj` not in `allowed` (besides "comment").
  void only(const Json& obj, const std::string& path, std::initializer_list<const char*> allowed) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (it.key() == "comment") continue;
      if (std::find_if(allowed.begin(), allowed.end(), [&](const char* a) { return it.key() == a; }) != allowed.end()) {
        continue;
      }
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      fail(member(path, it.key()), "unknown field (expected one of: " + list + ", comment)");
    }
  }

  void object(const Json& j, const std::string& path, const char* what) const {
    if (!j.is_object()) fail(path, std::string("expected ") + what + " (a JSON object), got " + j.type_name());
  }

  const Json& require(const Json& obj, const char* key, const std::string& path) const {
    const auto it = obj.find(key);
    if (it == obj.end()) fail(member(path, key), "missing");
    return *it;
  }

  static const Json* find(const Json& obj, const char* key) {
    const auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }

  float real(const Json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, std::string("expected a number, got ") + j.type_name());
    const double d = j.get<double>();
    const auto f = static_cast<float>(d);
    if (!std::isfinite(d) || !std::isfinite(f)) fail(path, "not a finite float (" + shown(j) + ")");
    return f;
  }

  float real_at_least(const Json& j, const std::string& path, float lo, const char* why) const {
    const float f = real(j, path);
    if (!(f >= lo)) fail(path, std::string(why) + " (" + shown(j) + ")");
    return f;
  }

  Vec2 vec2(const Json& j, const std::string& path) const {
    if (!j.is_array()) fail(path, std::string("expected [x, y], got ") + j.type_name());
    if (j.size() == 3) fail(path, "3D coordinates: scenes are 2D");
    if (j.size() != 2) fail(path, "expected 2 numbers, got " + std::to_string(j.size()));
    return {real(j[0], element(path, 0)), real(j[1], element(path, 1))};
  }

  bool boolean(const Json& j, const std::string& path) const {
    if (!j.is_boolean()) fail(path, std::string("expected true or false, got ") + j.type_name());
    return j.get<bool>();
  }

  std::uint64_t integer(const Json& j, const std::string& path, std::uint64_t max) const {
    if (j.is_number_unsigned()) {
      const auto v = j.get<std::uint64_t>();
      if (v > max) fail(path, "out of range (" + shown(j) + " > " + std::to_string(max) + ")");
      return v;
    }
    if (j.is_number_integer()) fail(path, "must be >= 0 (" + shown(j) + ")");
    fail(path, std::string("expected a non-negative integer, got ") + (j.is_number() ? shown(j) : j.type_name()));
  }

  std::vector<Vec2> points(const Json& j, const std::string& path) const {
    if (!j.is_array()) fail(path, std::string("expected an array of [x, y] points, got ") + j.type_name());
    std::vector<Vec2> out;
    out.reserve(j.size());
    for (std::size_t i = 0; i < j.size(); ++i) out.push_back(vec2(j[i], element(path, i)));
    return out;
  }

  float radius(const Json& shape, const std::string& path, bool required) const {
    const Json* r = find(shape, "radius");
    if (r == nullptr) {
      if (required) fail(member(path, "radius"), "missing");
      return 0.0f;
    }
    const float v = real(*r, member(path, "radius"));
    if (v < 0.0f) fail(member(path, "radius"), "negative (" + shown(*r) + ")");
    return v;
  }

  /// One shape object; appends its convex pieces (several for concave polygons and polylines).
  void shape(const Json& j, const std::string& path, std::vector<Shape2D>& out) const {
    object(j, path, "a shape");
    const Json& type_json = require(j, "type", path);
    if (!type_json.is_string()) fail(member(path, "type"), std::string("expected a string, got ") + type_json.type_name());
    const std::string type = type_json.get<std::string>();
    if (type == "circle") {
      only(j, path, {"type", "center", "radius"});
      const Json* c = find(j, "center");
      const Vec2 center = c == nullptr ? Vec2{0.0f, 0.0f} : vec2(*c, member(path, "center"));
      const float r = radius(j, path, true);
      out.emplace_back(build(path, [&] { return make_circle(center, r); }));
    } else if (type == "capsule") {
      only(j, path, {"type", "a", "b", "radius"});
      const Vec2 a = vec2(require(j, "a", path), member(path, "a"));
      const Vec2 b = vec2(require(j, "b", path), member(path, "b"));
      const float r = radius(j, path, true);
      out.emplace_back(build(path, [&] { return make_capsule(a, b, r); }));
    } else if (type == "segment") {
      only(j, path, {"type", "a", "b"});
      const Vec2 a = vec2(require(j, "a", path), member(path, "a"));
      const Vec2 b = vec2(require(j, "b", path), member(path, "b"));
      out.emplace_back(build(path, [&] { return make_segment(a, b); }));
    } else if (type == "box") {
      only(j, path, {"type", "half", "radius"});
      const std::string half_path = member(path, "half");
      const Vec2 half = vec2(require(j, "half", path), half_path);
      if (!(half.x > 0.0f && half.y > 0.0f)) fail(half_path, "half extents must be > 0");
      const float r = radius(j, path, false);
      out.emplace_back(build(path, [&] { return make_box(half, r); }));
    } else if (type == "polygon") {
      only(j, path, {"type", "vertices", "radius", "concave"});
      const std::string vertices_path = member(path, "vertices");
      const std::vector<Vec2> vertices = points(require(j, "vertices", path), vertices_path);
      const Json* concave_json = find(j, "concave");
      const bool concave = concave_json != nullptr && boolean(*concave_json, member(path, "concave"));
      if (concave) {
        if (find(j, "radius") != nullptr) fail(member(path, "radius"), "not allowed on a concave polygon");
        std::vector<Shape2D> pieces;
        try {
          pieces = convex_pieces(vertices, vertices_path);  // its messages start with the path
        } catch (const InvalidInput& e) {
          throw InvalidInput(file_ + ": " + e.what());
        }
        out.insert(out.end(), pieces.begin(), pieces.end());
      } else {
        const float r = radius(j, path, false);
        try {
          out.emplace_back(make_convex_polygon(vertices, r));
        } catch (const InvalidInput& e) {
          fail(vertices_path, std::string(e.what()) +
                                  "; for a concave or clockwise outline add \"concave\": true");
        }
      }
    } else if (type == "polyline") {
      only(j, path, {"type", "points", "closed"});
      const std::string points_path = member(path, "points");
      const std::vector<Vec2> p = points(require(j, "points", path), points_path);
      if (p.size() < 2) fail(points_path, "needs at least 2 points, got " + std::to_string(p.size()));
      const Json* closed_json = find(j, "closed");
      const bool closed = closed_json != nullptr && boolean(*closed_json, member(path, "closed"));
      if (closed && p.size() < 3) fail(points_path, "a closed polyline needs at least 3 points");
      const std::size_t links = closed ? p.size() : p.size() - 1;
      for (std::size_t i = 0; i < links; ++i) {
        const std::size_t k = (i + 1) % p.size();
        if (p[i] == p[k]) fail(element(points_path, k), "repeats " + element(points_path, i) + " (a zero-length link)");
        out.emplace_back(build(element(points_path, k), [&] { return make_segment(p[i], p[k]); }));
      }
    } else if (type == "sphere" || type == "hull" || type == "triangle") {
      fail(member(path, "type"), "\"" + type + "\" is a 3D shape: scenes are 2D");
    } else {
      fail(member(path, "type"),
           "unknown shape type \"" + type + "\" (expected circle, capsule, box, polygon, segment or polyline)");
    }
  }

  Transform transform(const Json& j, const std::string& path) const {
    if (!j.is_object()) fail(path, "expected {\"p\": [x, y], \"angle\": radians}");
    only(j, path, {"p", "angle"});
    Transform xf;
    if (const Json* p = find(j, "p")) xf.p = vec2(*p, member(path, "p"));
    if (const Json* a = find(j, "angle")) xf = Transform::from(xf.p, real(*a, member(path, "angle")));
    return xf;
  }

  /// The fields statics and bodies share. Returns the shapes; fills the rest through the refs.
  std::vector<Shape2D> collider(const Json& j, const std::string& path, Transform& xf, std::uint64_t& user,
                                CollisionFilter& filter, bool& sensor) const {
    const Json* one = find(j, "shape");
    const Json* many = find(j, "shapes");
    if (one != nullptr && many != nullptr) fail(path, "give \"shape\" or \"shapes\", not both");
    if (one == nullptr && many == nullptr) fail(member(path, "shapes"), "missing (give \"shape\" or \"shapes\")");
    std::vector<Shape2D> shapes;
    if (one != nullptr) {
      shape(*one, member(path, "shape"), shapes);
    } else {
      const std::string shapes_path = member(path, "shapes");
      if (!many->is_array()) fail(shapes_path, std::string("expected an array of shapes, got ") + many->type_name());
      if (many->empty()) fail(shapes_path, "empty (at least one shape)");
      for (std::size_t i = 0; i < many->size(); ++i) shape((*many)[i], element(shapes_path, i), shapes);
    }
    if (shapes.size() > kSceneMaxPieces) {
      fail(path, std::to_string(shapes.size()) + " convex pieces, more than " + std::to_string(kSceneMaxPieces));
    }
    if (const Json* t = find(j, "transform")) xf = transform(*t, member(path, "transform"));
    if (const Json* u = find(j, "user_id")) user = integer(*u, member(path, "user_id"), std::numeric_limits<std::uint64_t>::max());
    constexpr std::uint64_t kMaxBits = std::numeric_limits<std::uint32_t>::max();
    if (const Json* l = find(j, "layer")) filter.layer = static_cast<std::uint32_t>(integer(*l, member(path, "layer"), kMaxBits));
    if (const Json* m = find(j, "mask")) filter.mask = static_cast<std::uint32_t>(integer(*m, member(path, "mask"), kMaxBits));
    if (const Json* s = find(j, "sensor")) sensor = boolean(*s, member(path, "sensor"));
    return shapes;
  }

  StaticDef static_def(const Json& j, const std::string& path) const {
    object(j, path, "a static");
    only(j, path, {"shape", "shapes", "transform", "user_id", "layer", "mask", "sensor"});
    StaticDef def;
    def.shapes = collider(j, path, def.transform, def.user_id, def.filter, def.sensor);
    return def;
  }

  BodyDef body_def(const Json& j, const std::string& path) const {
    object(j, path, "a body");
    only(j, path, {"shape", "shapes", "transform", "user_id", "layer", "mask", "sensor", "velocity",
                   "angular_velocity", "bullet"});
    BodyDef def;
    def.shapes = collider(j, path, def.transform, def.user_id, def.filter, def.sensor);
    if (const Json* v = find(j, "velocity")) def.velocity = vec2(*v, member(path, "velocity"));
    if (const Json* w = find(j, "angular_velocity")) def.angular_velocity = real(*w, member(path, "angular_velocity"));
    if (const Json* b = find(j, "bullet")) def.bullet = boolean(*b, member(path, "bullet"));
    return def;
  }

  Aabb bounds(const Json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 4) fail(path, "expected [minx, miny, maxx, maxy]");
    Aabb box{{real(j[0], element(path, 0)), real(j[1], element(path, 1))},
             {real(j[2], element(path, 2)), real(j[3], element(path, 3))}};
    if (!(box.min.x < box.max.x && box.min.y < box.max.y)) fail(path, "empty or inverted (min must be < max)");
    return box;
  }

  /// `[min, max]` with lo <= min <= max (min > lo when `strict`).
  std::pair<float, float> range(const Json& j, const std::string& path, float lo, bool strict) const {
    const Vec2 v = vec2(j, path);
    if (strict ? !(v.x > lo) : !(v.x >= lo)) fail(element(path, 0), std::string("must be ") + (strict ? "> " : ">= ") + std::to_string(lo));
    if (!(v.x <= v.y)) fail(path, "min > max");
    return {v.x, v.y};
  }

  SceneSpawn spawn(const Json* j, const std::string& path, const Aabb& box) const {
    const float side = std::min(box.max.x - box.min.x, box.max.y - box.min.y);
    SceneSpawn s;
    s.min_radius = kSpawnMinRadiusFraction * side;
    s.max_radius = kSpawnMaxRadiusFraction * side;
    s.min_speed = kSpawnMinSpeedFraction * side;
    s.max_speed = kSpawnMaxSpeedFraction * side;
    s.bullet_speed = kSpawnBulletSpeedFraction * side;
    if (j == nullptr) return s;
    object(*j, path, "a spawn section");
    only(*j, path, {"count", "seed", "radius", "speed", "bullets", "bullet_speed"});
    s.count = static_cast<int>(integer(require(*j, "count", path), member(path, "count"), kSceneMaxSpawn));
    s.bullets = s.count / kSceneBodiesPerBullet;
    if (const Json* v = find(*j, "seed")) {
      s.seed = static_cast<std::uint32_t>(integer(*v, member(path, "seed"), std::numeric_limits<std::uint32_t>::max()));
    }
    if (const Json* v = find(*j, "radius")) {
      std::tie(s.min_radius, s.max_radius) = range(*v, member(path, "radius"), 0.0f, true);
      if (!(s.max_radius < kSpawnMaxRadiusLimit * side)) {
        fail(element(member(path, "radius"), 1), "too large for the bounds (must be < a quarter of the smaller side)");
      }
    }
    if (const Json* v = find(*j, "speed")) std::tie(s.min_speed, s.max_speed) = range(*v, member(path, "speed"), 0.0f, false);
    if (const Json* v = find(*j, "bullets")) {
      s.bullets = static_cast<int>(integer(*v, member(path, "bullets"), static_cast<std::uint64_t>(s.count)));
    }
    if (const Json* v = find(*j, "bullet_speed")) {
      s.bullet_speed = real(*v, member(path, "bullet_speed"));
      if (!(s.bullet_speed > 0.0f)) fail(member(path, "bullet_speed"), "must be > 0 (" + shown(*v) + ")");
    }
    return s;
  }

  SceneLaser laser(const Json& j, const std::string& path) const {
    object(j, path, "a laser");
    only(j, path, {"origin", "translation", "sweep"});
    SceneLaser l;
    l.ray.origin = vec2(require(j, "origin", path), member(path, "origin"));
    l.ray.translation = vec2(require(j, "translation", path), member(path, "translation"));
    if (l.ray.translation == Vec2{0.0f, 0.0f}) fail(member(path, "translation"), "must not be zero");
    if (const Json* s = find(j, "sweep")) l.sweep = real(*s, member(path, "sweep"));
    return l;
  }

  /// Bodies start inside the bounds and clear of the solid statics they interact with.
  void check_start(const SceneDescription& scene) const {
    const Vec2 size = scene.bounds.max - scene.bounds.min;
    const float tolerance = kSceneStartOverlapFraction * std::max(size.x, size.y);
    for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
      const BodyDef& body = scene.bodies[b];
      const std::string path = element("bodies", b);
      for (const Shape2D& piece : body.shapes) {
        const Aabb box = compute_aabb(piece, body.transform);
        if (!(box.min.x >= scene.bounds.min.x && box.min.y >= scene.bounds.min.y && box.max.x <= scene.bounds.max.x &&
              box.max.y <= scene.bounds.max.y)) {
          std::ostringstream why;
          why << "reaches outside the bounds (its box [" << box.min.x << ", " << box.min.y << ", " << box.max.x << ", "
              << box.max.y << "])";
          fail(path, why.str());
        }
      }
      if (body.sensor) continue;
      for (std::size_t s = 0; s < scene.statics.size(); ++s) {
        const StaticDef& st = scene.statics[s];
        if (st.sensor || !should_collide(body.filter, st.filter)) continue;
        for (const Shape2D& piece : body.shapes) {
          for (const Shape2D& other : st.shapes) {
            if (!overlap(compute_aabb(piece, body.transform), compute_aabb(other, st.transform))) continue;
            const float depth = contact(piece, body.transform, other, st.transform).max_depth();
            if (depth > tolerance) {
              std::ostringstream why;
              why << "starts inside statics[" << s << "] (overlap depth " << depth << ")";
              fail(path, why.str());
            }
          }
        }
      }
    }
  }

  SceneDescription scene(const Json& root) const {
    object(root, "", "a scene");
    only(root, "", {"bounds", "walls", "statics", "bodies", "spawn", "laser"});
    SceneDescription out;
    out.bounds = bounds(require(root, "bounds", ""), "bounds");
    const float side = std::min(out.bounds.max.x - out.bounds.min.x, out.bounds.max.y - out.bounds.min.y);
    out.wall_thickness = kSceneDefaultWallFraction * side;
    if (const Json* w = find(root, "walls")) out.wall_thickness = real_at_least(*w, "walls", 0.0f, "must be >= 0");
    if (const Json* list = find(root, "statics")) {
      if (!list->is_array()) fail("statics", std::string("expected an array, got ") + list->type_name());
      for (std::size_t i = 0; i < list->size(); ++i) out.statics.push_back(static_def((*list)[i], element("statics", i)));
    }
    if (const Json* list = find(root, "bodies")) {
      if (!list->is_array()) fail("bodies", std::string("expected an array, got ") + list->type_name());
      for (std::size_t i = 0; i < list->size(); ++i) out.bodies.push_back(body_def((*list)[i], element("bodies", i)));
    }
    out.spawn = spawn(find(root, "spawn"), "spawn", out.bounds);
    if (const Json* l = find(root, "laser")) out.laser = laser(*l, "laser");
    check_start(out);
    return out;
  }

 private:
  std::string file_;
};

/// nlohmann's message without its "[json.exception.parse_error.101] parse error " prefix: "at
/// line 3, column 5: syntax error while parsing ...", or "number overflow parsing '1e400'".
std::string syntax_reason(const std::string& what) {
  std::size_t at = what.find("] ");
  std::string reason = at == std::string::npos ? what : what.substr(at + 2);
  const std::string prefix = "parse error ";
  if (reason.rfind(prefix, 0) == 0) reason = reason.substr(prefix.size());
  return reason;
}

}  // namespace

SceneDescription parse_scene_json(std::string_view text, const std::filesystem::path& name) {
  const SceneReader reader(name.generic_string());
  const std::string copy(text);
  Json root;
  try {
    root = Json::parse(copy);
  } catch (const Json::parse_error& e) {
    reader.fail(io::json_path_at_syntax_error(copy), "JSON syntax error " + syntax_reason(e.what()));
  } catch (const Json::exception& e) {  // a number too large for a double (1e400): out_of_range.406
    reader.fail(io::json_path_at_syntax_error(copy), std::string("not a finite number (") + syntax_reason(e.what()) + ")");
  }
  SceneDescription scene;
  try {
    scene = reader.scene(root);
  } catch (const InvalidInput&) {
    throw;
  } catch (const std::exception& e) {  // a path the checks above missed: still an error, never a crash
    reader.fail("", std::string("cannot be read as a scene: ") + e.what());
  }
  scene.path = name;
  return scene;
}

SceneDescription load_scene_json(const std::filesystem::path& path) {
  const std::optional<std::string> text = io::read_text_file(path);
  if (!text) throw InvalidInput(path.generic_string() + ": cannot be read");
  return parse_scene_json(*text, path);
}

}  // namespace collide
