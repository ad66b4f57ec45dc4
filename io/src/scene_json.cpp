// Scene JSON (docs/scene-json.md) -> World2D definitions. Every value is checked before use and
// every rejection names the file and the JSON path of the field. Text, numbers, shapes and
// transforms are read by the shared JSON vocabulary (collide/io/shape_json.hpp, the same as
// `collide query`); this file adds the scene's own objects.

#include <collide/io/scene_json.hpp>

#include "text_file.hpp"

#include <collide/core/error.hpp>
#include <collide/io/shape_json.hpp>
#include <collide/narrow/contact.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
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

/// A value as JSON prints it back (1e39 -> 1e+39), for messages.
std::string shown(const Json& j) { return j.dump(); }

/// Reads one file. The shapes, transforms, numbers and field checks are the shared JSON
/// vocabulary (collide/io/shape_json.hpp); this reader adds the scene's own objects. Every
/// rejection is a JsonFieldError; `parse_scene_json` puts the file's name in front.
class SceneReader {
 public:
  static std::uint64_t integer(const Json& j, const JsonPath& path, std::uint64_t max) {
    if (j.is_number_unsigned()) {
      const auto v = j.get<std::uint64_t>();
      if (v > max) fail_json(path, "out of range (" + shown(j) + " > " + std::to_string(max) + ")");
      return v;
    }
    if (j.is_number_integer()) fail_json(path, "must be >= 0 (" + shown(j) + ")");
    fail_json(path, "expected a non-negative integer, got " + (j.is_number() ? shown(j) : json_kind(j)));
  }

  static float real_at_least(const Json& j, const JsonPath& path, float lo, const char* why) {
    const float f = float_from_json(j, path);
    if (!(f >= lo)) fail_json(path, std::string(why) + " (" + shown(j) + ")");
    return f;
  }

  /// The fields statics and bodies share. Returns the shapes; fills the rest through the refs.
  static std::vector<Shape2D> collider(const Json& j, const JsonPath& path, Transform& xf, std::uint64_t& user,
                                       CollisionFilter& filter, bool& sensor) {
    const Json* one = find_member(j, "shape");
    const Json* many = find_member(j, "shapes");
    if (one != nullptr && many != nullptr) fail_json(path, "give \"shape\" or \"shapes\", not both");
    if (one == nullptr && many == nullptr) fail_json(path.member("shapes"), "missing (give \"shape\" or \"shapes\")");
    std::vector<Shape2D> shapes;
    if (one != nullptr) {
      shape_pieces_from_json(*one, path.member("shape"), shapes);
    } else {
      const JsonPath shapes_path = path.member("shapes");
      if (!many->is_array()) fail_json(shapes_path, "expected an array of shapes, got " + json_kind(*many));
      if (many->empty()) fail_json(shapes_path, "empty (at least one shape)");
      for (std::size_t i = 0; i < many->size(); ++i) shape_pieces_from_json((*many)[i], shapes_path.element(i), shapes);
    }
    if (shapes.size() > kSceneMaxPieces) {
      fail_json(path, std::to_string(shapes.size()) + " convex pieces, more than " + std::to_string(kSceneMaxPieces));
    }
    if (const Json* t = find_member(j, "transform")) xf = transform_from_json(*t, path.member("transform"));
    if (const Json* u = find_member(j, "user_id")) {
      user = integer(*u, path.member("user_id"), std::numeric_limits<std::uint64_t>::max());
    }
    constexpr std::uint64_t kMaxBits = std::numeric_limits<std::uint32_t>::max();
    if (const Json* l = find_member(j, "layer")) {
      filter.layer = static_cast<std::uint32_t>(integer(*l, path.member("layer"), kMaxBits));
    }
    if (const Json* m = find_member(j, "mask")) {
      filter.mask = static_cast<std::uint32_t>(integer(*m, path.member("mask"), kMaxBits));
    }
    if (const Json* s = find_member(j, "sensor")) sensor = bool_from_json(*s, path.member("sensor"));
    return shapes;
  }

  static StaticDef static_def(const Json& j, const JsonPath& path) {
    check_object(j, path, "a static");
    check_fields(j, path, {"shape", "shapes", "transform", "user_id", "layer", "mask", "sensor"});
    StaticDef def;
    def.shapes = collider(j, path, def.transform, def.user_id, def.filter, def.sensor);
    return def;
  }

  static BodyDef body_def(const Json& j, const JsonPath& path) {
    check_object(j, path, "a body");
    check_fields(j, path, {"shape", "shapes", "transform", "user_id", "layer", "mask", "sensor", "velocity",
                           "angular_velocity", "bullet"});
    BodyDef def;
    def.shapes = collider(j, path, def.transform, def.user_id, def.filter, def.sensor);
    if (const Json* v = find_member(j, "velocity")) def.velocity = vec2_from_json(*v, path.member("velocity"));
    if (const Json* w = find_member(j, "angular_velocity")) {
      def.angular_velocity = float_from_json(*w, path.member("angular_velocity"));
    }
    if (const Json* b = find_member(j, "bullet")) def.bullet = bool_from_json(*b, path.member("bullet"));
    return def;
  }

  static Aabb bounds(const Json& j, const JsonPath& path) {
    if (!j.is_array() || j.size() != 4) fail_json(path, "expected [minx, miny, maxx, maxy]");
    Aabb box{{float_from_json(j[0], path.element(0)), float_from_json(j[1], path.element(1))},
             {float_from_json(j[2], path.element(2)), float_from_json(j[3], path.element(3))}};
    if (!(box.min.x < box.max.x && box.min.y < box.max.y)) fail_json(path, "empty or inverted (min must be < max)");
    return box;
  }

  /// `[min, max]` with lo <= min <= max (min > lo when `strict`).
  static std::pair<float, float> range(const Json& j, const JsonPath& path, float lo, bool strict) {
    const Vec2 v = vec2_from_json(j, path);
    if (strict ? !(v.x > lo) : !(v.x >= lo)) {
      fail_json(path.element(0), std::string("must be ") + (strict ? "> " : ">= ") + std::to_string(lo));
    }
    if (!(v.x <= v.y)) fail_json(path, "min > max");
    return {v.x, v.y};
  }

  /// A spawn speed at `at` must be within the world's (World2D refuses faster bodies).
  static void within_world_speed(float speed, const JsonPath& at) {
    if (speed <= kMaxWorldSpeed) return;
    fail_json(at, "beyond the world's speed range (kMaxWorldSpeed, " +
                      std::to_string(static_cast<long long>(kMaxWorldSpeed)) + ")");
  }

  static SceneSpawn spawn(const Json* j, const JsonPath& path, const Aabb& box) {
    const float side = std::min(box.max.x - box.min.x, box.max.y - box.min.y);
    SceneSpawn s;
    s.min_radius = kSpawnMinRadiusFraction * side;
    s.max_radius = kSpawnMaxRadiusFraction * side;
    s.min_speed = kSpawnMinSpeedFraction * side;
    s.max_speed = kSpawnMaxSpeedFraction * side;
    // Bounds up to 2^31 across are in range, so 2 L is capped at the world's speed range.
    s.bullet_speed = std::min(kSpawnBulletSpeedFraction * side, kMaxWorldSpeed);
    if (j == nullptr) return s;
    check_object(*j, path, "a spawn section");
    check_fields(*j, path, {"count", "seed", "radius", "speed", "bullets", "bullet_speed"});
    s.count = static_cast<int>(integer(require_member(*j, path, "count"), path.member("count"), kSceneMaxSpawn));
    s.bullets = s.count / kSceneBodiesPerBullet;
    if (const Json* v = find_member(*j, "seed")) {
      s.seed = static_cast<std::uint32_t>(integer(*v, path.member("seed"), std::numeric_limits<std::uint32_t>::max()));
    }
    if (const Json* v = find_member(*j, "radius")) {
      std::tie(s.min_radius, s.max_radius) = range(*v, path.member("radius"), 0.0f, true);
      if (!(s.max_radius < kSpawnMaxRadiusLimit * side)) {
        const JsonPath radius = path.member("radius");
        fail_json(radius.element(1), "too large for the bounds (must be < a quarter of the smaller side)");
      }
    }
    if (const Json* v = find_member(*j, "speed")) {
      std::tie(s.min_speed, s.max_speed) = range(*v, path.member("speed"), 0.0f, false);
      const JsonPath speed = path.member("speed");
      within_world_speed(s.max_speed, speed.element(1));
    }
    if (const Json* v = find_member(*j, "bullets")) {
      s.bullets = static_cast<int>(integer(*v, path.member("bullets"), static_cast<std::uint64_t>(s.count)));
    }
    if (const Json* v = find_member(*j, "bullet_speed")) {
      s.bullet_speed = float_from_json(*v, path.member("bullet_speed"));
      if (!(s.bullet_speed > 0.0f)) fail_json(path.member("bullet_speed"), "must be > 0 (" + shown(*v) + ")");
      within_world_speed(s.bullet_speed, path.member("bullet_speed"));
    }
    return s;
  }

  static SceneLaser laser(const Json& j, const JsonPath& path) {
    check_object(j, path, "a laser");
    check_fields(j, path, {"origin", "translation", "sweep"});
    SceneLaser l;
    l.ray.origin = vec2_from_json(require_member(j, path, "origin"), path.member("origin"));
    l.ray.translation = vec2_from_json(require_member(j, path, "translation"), path.member("translation"));
    if (l.ray.translation == Vec2{0.0f, 0.0f}) fail_json(path.member("translation"), "must not be zero");
    if (const Json* s = find_member(j, "sweep")) l.sweep = float_from_json(*s, path.member("sweep"));
    return l;
  }

  /// Bodies start inside the bounds and clear of the solid statics they interact with.
  static void check_start(const SceneDescription& scene) {
    const Vec2 size = scene.bounds.max - scene.bounds.min;
    const float tolerance = kSceneStartOverlapFraction * std::max(size.x, size.y);
    const JsonPath top;
    const JsonPath bodies = top.member("bodies");
    for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
      const BodyDef& body = scene.bodies[b];
      const JsonPath path = bodies.element(b);
      for (const Shape2D& piece : body.shapes) {
        const Aabb box = compute_aabb(piece, body.transform);
        if (!(box.min.x >= scene.bounds.min.x && box.min.y >= scene.bounds.min.y && box.max.x <= scene.bounds.max.x &&
              box.max.y <= scene.bounds.max.y)) {
          std::ostringstream why;
          why << "reaches outside the bounds (its box [" << box.min.x << ", " << box.min.y << ", " << box.max.x << ", "
              << box.max.y << "])";
          fail_json(path, why.str());
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
              fail_json(path, why.str());
            }
          }
        }
      }
    }
  }

  static SceneDescription scene(const Json& root) {
    const JsonPath top;
    check_object(root, top, "a scene");
    check_fields(root, top, {"bounds", "walls", "statics", "bodies", "spawn", "laser"});
    SceneDescription out;
    out.bounds = bounds(require_member(root, top, "bounds"), top.member("bounds"));
    const float side = std::min(out.bounds.max.x - out.bounds.min.x, out.bounds.max.y - out.bounds.min.y);
    out.wall_thickness = kSceneDefaultWallFraction * side;
    if (const Json* w = find_member(root, "walls")) {
      out.wall_thickness = real_at_least(*w, top.member("walls"), 0.0f, "must be >= 0");
    }
    // The world's coordinate range (kMaxWorldCoordinate), here so a scene that loads can run:
    // the bounds with the walls around them, then every static and body.
    const Vec2 walls{out.wall_thickness, out.wall_thickness};
    check_world_range(Aabb{out.bounds.min - walls, out.bounds.max + walls},
                      out.wall_thickness > 0.0f ? "bounds (with the walls)" : "bounds");
    if (const Json* list = find_member(root, "statics")) {
      const JsonPath path = top.member("statics");
      if (!list->is_array()) fail_json(path, "expected an array, got " + json_kind(*list));
      for (std::size_t i = 0; i < list->size(); ++i) {
        out.statics.push_back(static_def((*list)[i], path.element(i)));
        check_world_range(out.statics.back().shapes, out.statics.back().transform, path.element(i).str());
      }
    }
    if (const Json* list = find_member(root, "bodies")) {
      const JsonPath path = top.member("bodies");
      if (!list->is_array()) fail_json(path, "expected an array, got " + json_kind(*list));
      for (std::size_t i = 0; i < list->size(); ++i) {
        out.bodies.push_back(body_def((*list)[i], path.element(i)));
        check_world_range(out.bodies.back().shapes, out.bodies.back().transform, path.element(i).str());
        check_world_velocity(out.bodies.back().velocity, out.bodies.back().angular_velocity, path.element(i).str());
      }
    }
    out.spawn = spawn(find_member(root, "spawn"), top.member("spawn"), out.bounds);
    if (const Json* l = find_member(root, "laser")) out.laser = laser(*l, top.member("laser"));
    check_start(out);
    return out;
  }
};

}  // namespace

SceneDescription parse_scene_json(std::string_view text, const std::filesystem::path& name) {
  const std::string file = name.generic_string();
  SceneDescription scene;
  try {
    scene = SceneReader::scene(parse_json(text));
  } catch (const InvalidInput& e) {  // JsonFieldError: "PATH: reason"
    throw InvalidInput(file + ": " + e.what());
  } catch (const std::exception& e) {  // a path the checks above missed: still an error, never a crash
    throw InvalidInput(file + ": root: cannot be read as a scene: " + e.what());
  }
  scene.path = name;
  return scene;
}

SceneDescription load_scene_json(const std::filesystem::path& path) {
  std::string why;
  const std::optional<std::string> text = io::read_text_file(path, why);
  if (!text) throw InvalidInput(path.generic_string() + ": " + why);
  return parse_scene_json(*text, path);
}

}  // namespace collide
