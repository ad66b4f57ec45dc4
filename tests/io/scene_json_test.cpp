// Scene JSON loader: the example scenes load with the values their files hold (checked field by
// field against the text of the file, and piece areas against the outlines' shoelace areas),
// every bad field is an InvalidInput that names the file and the JSON path, and mangled files
// are errors, never crashes.

#include <collide/core/error.hpp>
#include <collide/io/scene_json.hpp>
#include <collide/io/tiled.hpp>

#include "support/test_util.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <typeinfo>
#include <vector>

namespace collide {
namespace {

namespace fs = std::filesystem;

const fs::path kScenes = fs::path(COLLIDE_EXAMPLES_DIR) / "scenes";

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Shoelace area of an outline (either winding: the absolute value).
double outline_area(const std::vector<Vec2>& outline) {
  double twice = 0.0;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const Vec2 a = outline[i], b = outline[(i + 1) % outline.size()];
    twice += static_cast<double>(a.x) * b.y - static_cast<double>(b.x) * a.y;
  }
  return std::abs(twice) / 2.0;
}

/// Summed area of convex polygon pieces, each counter-clockwise; every vertex must be one of
/// the outline's (Hertel-Mehlhorn over ear clipping adds no vertex).
double pieces_area(const std::vector<Shape2D>& pieces, const std::vector<Vec2>& outline) {
  double area = 0.0;
  for (const Shape2D& s : pieces) {
    const auto* p = std::get_if<Polygon>(&s);
    if (p == nullptr) {
      ADD_FAILURE() << "a piece is a " << type_name(s);
      continue;
    }
    const double a = signed_area(std::span<const Vec2>(p->vertices.data(), static_cast<std::size_t>(p->count)));
    EXPECT_GT(a, 0.0);
    area += a;
    for (int i = 0; i < p->count; ++i) {
      bool found = false;
      for (const Vec2 v : outline) found = found || v == p->vertices[static_cast<std::size_t>(i)];
      EXPECT_TRUE(found) << "vertex (" << p->vertices[i].x << ", " << p->vertices[i].y << ") not in the outline";
    }
  }
  return area;
}

void expect_transform(const Transform& xf, Vec2 p, float angle) {
  const Transform want = Transform::from(p, angle);
  EXPECT_EQ(xf.p, want.p);
  EXPECT_EQ(xf.q.c, want.q.c);
  EXPECT_EQ(xf.q.s, want.q.s);
}

void expect_default_filter(const CollisionFilter& f) {
  EXPECT_EQ(f.layer, 1u);
  EXPECT_EQ(f.mask, 0xffffffffu);
}

// Every value below is read off examples/scenes/pinball.json by eye.
TEST(SceneJson, PinballExampleLoadsWhatTheFileSays) {
  const fs::path file = kScenes / "pinball.json";
  const SceneDescription s = load_scene_json(file);
  EXPECT_EQ(s.path, file);
  EXPECT_EQ(s.bounds.min, Vec2(-20.0f, -30.0f));
  EXPECT_EQ(s.bounds.max, Vec2(20.0f, 30.0f));
  EXPECT_EQ(s.wall_thickness, 0.5f);
  ASSERT_EQ(s.statics.size(), 13u);
  ASSERT_EQ(s.bodies.size(), 10u);

  // Star bumper: a concave 10-gon, its pieces cover exactly its area.
  const std::vector<Vec2> star = {{0, 4},           {-1.058f, 1.456f}, {-3.804f, 1.236f}, {-1.712f, -0.556f},
                                  {-2.351f, -3.236f}, {0, -1.8f},        {2.351f, -3.236f},  {1.712f, -0.556f},
                                  {3.804f, 1.236f},   {1.058f, 1.456f}};
  EXPECT_EQ(s.statics[0].user_id, 10u);
  expect_transform(s.statics[0].transform, {0, 8}, 0.2f);
  EXPECT_GE(s.statics[0].shapes.size(), 4u);  // a five-pointed star needs at least 4 convex pieces
  EXPECT_NEAR(pieces_area(s.statics[0].shapes, star), outline_area(star), 1e-4);
  // Slingshots: the same outline in both windings (one mirrored): same area, same piece count.
  const std::vector<Vec2> left = {{0, 0}, {5, 2}, {5, 3}, {1, 1.4f}, {0, 4}};
  const std::vector<Vec2> right = {{0, 0}, {-5, 2}, {-5, 3}, {-1, 1.4f}, {0, 4}};
  EXPECT_EQ(s.statics[1].shapes.size(), 2u);
  EXPECT_EQ(s.statics[2].shapes.size(), 2u);
  EXPECT_NEAR(pieces_area(s.statics[1].shapes, left), outline_area(left), 1e-5);
  EXPECT_NEAR(pieces_area(s.statics[2].shapes, right), outline_area(right), 1e-5);
  EXPECT_NEAR(outline_area(left), 2.5 + 2.0 + 2.0, 1e-5);  // by hand: the fan of triangles from (0, 0)
  expect_transform(s.statics[2].transform, {16, -18}, 0.0f);
  // Top arc: a chain of 8 segments through the 9 points, in order.
  const std::vector<Vec2> arc = {{-15.035f, 6.528f}, {-15.863f, 14.088f}, {-13.106f, 21.177f},
                                 {-7.388f, 26.192f}, {0, 28},               {7.388f, 26.192f},
                                 {13.106f, 21.177f}, {15.863f, 14.088f},    {15.035f, 6.528f}};
  ASSERT_EQ(s.statics[3].shapes.size(), 8u);
  for (std::size_t i = 0; i < 8; ++i) {
    const auto* seg = std::get_if<Segment>(&s.statics[3].shapes[i]);
    ASSERT_NE(seg, nullptr);
    EXPECT_EQ(seg->a, arc[i]);
    EXPECT_EQ(seg->b, arc[i + 1]);
  }
  // Bumpers: one static, two circles.
  ASSERT_EQ(s.statics[4].shapes.size(), 2u);
  EXPECT_EQ(std::get<Circle>(s.statics[4].shapes[0]).center, Vec2(-8, 0));
  EXPECT_EQ(std::get<Circle>(s.statics[4].shapes[1]).center, Vec2(8, 0));
  EXPECT_EQ(std::get<Circle>(s.statics[4].shapes[1]).radius, 1.5f);
  expect_transform(s.statics[4].transform, {0, 18}, 0.0f);
  // Flippers, mirror, kickers.
  const Capsule& flipper = std::get<Capsule>(s.statics[6].shapes[0]);
  EXPECT_EQ(flipper.a, Vec2(3, -25));
  EXPECT_EQ(flipper.b, Vec2(9, -22));
  EXPECT_EQ(flipper.radius, 0.6f);
  EXPECT_EQ(std::get<Segment>(s.statics[7].shapes[0]).a, Vec2(-3, -8));
  const Polygon& kicker = std::get<Polygon>(s.statics[8].shapes[0]);
  EXPECT_EQ(kicker.count, 4);
  EXPECT_EQ(kicker.radius, 0.3f);
  EXPECT_EQ(kicker.vertices[0], Vec2(-2, -0.5f));  // make_box: lower-left first
  EXPECT_EQ(kicker.vertices[2], Vec2(2, 0.5f));
  expect_transform(s.statics[8].transform, {10, -5}, 0.6f);
  const Polygon& triangle = std::get<Polygon>(s.statics[9].shapes[0]);
  ASSERT_EQ(triangle.count, 3);
  EXPECT_EQ(triangle.vertices[1], Vec2(3, 0));  // kept in the file's order
  // Layers and sensors.
  EXPECT_EQ(s.statics[10].filter.layer, 8u);
  EXPECT_EQ(s.statics[10].filter.mask, 8u);
  EXPECT_TRUE(s.statics[11].sensor);
  EXPECT_EQ(s.statics[11].user_id, 900u);
  EXPECT_EQ(std::get<Polygon>(s.statics[11].shapes[0]).vertices[2], Vec2(3, 1));
  EXPECT_TRUE(s.statics[12].sensor);
  EXPECT_EQ(std::get<Circle>(s.statics[12].shapes[0]).radius, 1.2f);
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_FALSE(s.statics[i].sensor) << i;
    expect_default_filter(s.statics[i].filter);
  }

  // Bodies.
  for (std::size_t i = 0; i < 10; ++i) EXPECT_EQ(s.bodies[i].user_id, 100u + i);
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(s.bodies[i].filter.layer, 2u) << i;
    EXPECT_EQ(s.bodies[i].filter.mask, 0xffffffffu) << i;
  }
  expect_transform(s.bodies[0].transform, {-5, -12}, 0.0f);
  EXPECT_EQ(s.bodies[0].velocity, Vec2(6, 14));
  EXPECT_EQ(std::get<Circle>(s.bodies[0].shapes[0]).radius, 0.6f);
  expect_transform(s.bodies[5].transform, {-4, 24}, 0.3f);
  EXPECT_EQ(s.bodies[5].angular_velocity, 1.5f);
  EXPECT_EQ(std::get<Capsule>(s.bodies[5].shapes[0]).radius, 0.4f);
  const std::vector<Vec2> l_body = {{0, 0}, {2, 0}, {2, 0.6f}, {0.6f, 0.6f}, {0.6f, 2}, {0, 2}};
  EXPECT_EQ(s.bodies[6].shapes.size(), 2u);
  EXPECT_NEAR(pieces_area(s.bodies[6].shapes, l_body), 4.0 - 1.4 * 1.4, 1e-5);
  EXPECT_EQ(s.bodies[6].angular_velocity, -1.0f);
  for (std::size_t i = 0; i < 10; ++i) EXPECT_EQ(s.bodies[i].bullet, i == 7) << i;
  EXPECT_EQ(s.bodies[7].velocity, Vec2(300, 40));
  EXPECT_EQ(s.bodies[8].filter.layer, 4u);
  EXPECT_EQ(s.bodies[8].filter.mask, 1u);
  for (std::size_t i = 0; i < 10; ++i) EXPECT_EQ(s.bodies[i].sensor, i == 9) << i;

  // Spawn and laser.
  EXPECT_EQ(s.spawn.count, 40);
  EXPECT_EQ(s.spawn.seed, 7u);
  EXPECT_EQ(s.spawn.min_radius, 0.3f);
  EXPECT_EQ(s.spawn.max_radius, 0.6f);
  EXPECT_EQ(s.spawn.min_speed, 3.0f);
  EXPECT_EQ(s.spawn.max_speed, 12.0f);
  EXPECT_EQ(s.spawn.bullets, 2);
  EXPECT_EQ(s.spawn.bullet_speed, 150.0f);
  ASSERT_TRUE(s.laser.has_value());
  EXPECT_EQ(s.laser->ray.origin, Vec2(-19, -29));
  EXPECT_EQ(s.laser->ray.translation, Vec2(120, 180));
  EXPECT_EQ(s.laser->sweep, 0.01f);
}

TEST(SceneJson, ThinWallsExampleLoadsWhatTheFileSaysWithDefaultsFromTheBounds) {
  const SceneDescription s = load_scene_json(kScenes / "thin_walls.json");
  EXPECT_EQ(s.bounds.min, Vec2(-50, -5));
  EXPECT_EQ(s.wall_thickness, 0.05f);
  ASSERT_EQ(s.statics.size(), 9u);
  int segments = 0, boxes = 0;
  for (const StaticDef& st : s.statics) {
    for (const Shape2D& shape : st.shapes) {
      segments += std::holds_alternative<Segment>(shape) ? 1 : 0;
      boxes += std::holds_alternative<Polygon>(shape) ? 1 : 0;
    }
  }
  EXPECT_EQ(segments, 4 + 2 + 2);  // four segments, two polylines of two links
  EXPECT_EQ(boxes, 3);
  EXPECT_EQ(std::get<Polygon>(s.statics[3].shapes[0]).vertices[2], Vec2(0.02f, 4));
  expect_transform(s.statics[8].transform, {40, 0}, 0.785398f);
  ASSERT_EQ(s.bodies.size(), 2u);
  EXPECT_TRUE(s.bodies[0].bullet && s.bodies[1].bullet);
  EXPECT_EQ(s.bodies[1].velocity, Vec2(-1000, 7));
  EXPECT_EQ(s.spawn.count, 200);
  EXPECT_EQ(s.spawn.bullets, 200);
  EXPECT_EQ(s.spawn.seed, 1u);
  EXPECT_EQ(s.spawn.min_radius, 0.1f);
  EXPECT_EQ(s.spawn.bullet_speed, 1000.0f);
  // Not in the file: the speed range defaults to [L/60, L/12] of the smaller side L = 10.
  EXPECT_FLOAT_EQ(s.spawn.min_speed, 10.0f / 60.0f);
  EXPECT_FLOAT_EQ(s.spawn.max_speed, 10.0f / 12.0f);
  EXPECT_EQ(s.laser->sweep, 0.02f);
}

/// The message of the InvalidInput that parsing `text` throws (or "no error").
std::string error_of_text(const std::string& text) {
  try {
    (void)parse_scene_json(text, "s.json");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no error";
}

TEST(SceneJson, OmittedFieldsTakeTheDocumentedDefaults) {
  const SceneDescription s = parse_scene_json(R"({
    "bounds": [0, 0, 40, 20],
    "statics": [{"shape": {"type": "circle", "radius": 1}, "transform": {"angle": 0.5}}],
    "bodies": [{"shape": {"type": "circle", "radius": 1}, "transform": {"p": [10, 10]}}]
  })", "defaults.json");
  EXPECT_EQ(s.wall_thickness, kSceneDefaultWallFraction * 20.0f);
  EXPECT_EQ(s.statics[0].user_id, 0u);
  expect_default_filter(s.statics[0].filter);
  EXPECT_FALSE(s.statics[0].sensor);
  expect_transform(s.statics[0].transform, {0, 0}, 0.5f);
  EXPECT_EQ(std::get<Circle>(s.statics[0].shapes[0]).center, Vec2(0, 0));
  const BodyDef& b = s.bodies[0];
  EXPECT_EQ(b.velocity, Vec2(0, 0));
  EXPECT_EQ(b.angular_velocity, 0.0f);
  EXPECT_FALSE(b.bullet);
  EXPECT_FALSE(b.sensor);
  expect_default_filter(b.filter);
  expect_transform(b.transform, {10, 10}, 0.0f);
  // No spawn: count 0 and the defaults of the bounds (L = 20), for --bodies.
  EXPECT_EQ(s.spawn.count, 0);
  EXPECT_EQ(s.spawn.bullets, 0);
  EXPECT_EQ(s.spawn.seed, 1u);
  EXPECT_FLOAT_EQ(s.spawn.min_radius, 20.0f / 400.0f);
  EXPECT_FLOAT_EQ(s.spawn.max_radius, 20.0f / 150.0f);
  EXPECT_FLOAT_EQ(s.spawn.bullet_speed, 40.0f);
  EXPECT_FALSE(s.laser.has_value());
  // Bounds 2e9 across are in the coordinate range, but 2 L is beyond the speed range: the
  // default bullet speed is capped at kMaxWorldSpeed, so such a scene's bullets can be added.
  const SceneDescription huge = parse_scene_json(R"({"bounds": [-1e9, -1e9, 1e9, 1e9], "walls": 0})", "huge.json");
  EXPECT_EQ(huge.spawn.bullet_speed, kMaxWorldSpeed);
  // An explicit bullet speed or body velocity beyond it is an error naming the field.
  EXPECT_NE(error_of_text(R"({"bounds": [0, 0, 10, 10], "spawn": {"count": 1, "bullet_speed": 2e9}})")
                .find("spawn.bullet_speed: beyond the world's speed range (kMaxWorldSpeed"),
            std::string::npos);
  EXPECT_NE(error_of_text(R"({"bounds": [0, 0, 10, 10], "spawn": {"count": 1, "speed": [1, 2e9]}})")
                .find("spawn.speed[1]: beyond the world's speed range"),
            std::string::npos);
  EXPECT_NE(error_of_text(R"({"bounds": [0, 0, 10, 10], "bodies": [{"shape": {"type": "circle", "radius": 1},
    "transform": {"p": [5, 5]}, "velocity": [0, -1e25]}]})")
                .find("bodies[0] velocity: (0, -1e+25) beyond the speed range"),
            std::string::npos);
  // A spawn section with only a count: one bullet in 50.
  EXPECT_EQ(parse_scene_json(R"({"bounds": [0, 0, 1, 1], "spawn": {"count": 120}})", "s.json").spawn.bullets, 2);
  // Comments are allowed everywhere, and walls may be 0.
  const SceneDescription c = parse_scene_json(R"({"comment": 1, "bounds": [0, 0, 1, 1], "walls": 0,
    "statics": [{"comment": "x", "shape": {"comment": [], "type": "segment", "a": [0, 0], "b": [1, 0]}}]})", "c.json");
  EXPECT_EQ(c.wall_thickness, 0.0f);
  EXPECT_EQ(c.statics.size(), 1u);
}

/// The message of the InvalidInput that parsing `text` as file "bad.json" throws.
std::string error_of(const std::string& text) {
  try {
    (void)parse_scene_json(text, "bad.json");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no error";
}

/// A scene with bounds [0, 0, 10, 10] and `rest` (more top-level members) after them.
std::string scene_with(const std::string& rest) { return R"({"bounds": [0, 0, 10, 10])" + rest + "}"; }
/// ... with one static whose shape is `shape`.
std::string static_shape(const std::string& shape) { return scene_with(R"(, "statics": [{"shape": )" + shape + "}]"); }

TEST(SceneJson, EveryErrorNamesTheFileAndTheJsonPath) {
  struct Case {
    std::string text;
    std::string path;    // the message must start with "bad.json: <path>: "
    std::string reason;  // and contain this
  };
  const std::string good_static = R"({"shape": {"type": "circle", "radius": 1}})";
  std::string many = "[";  // a convex 65-gon: one vertex over the limit
  for (int i = 0; i < 65; ++i) {
    const float a = 6.2831853f * static_cast<float>(i) / 65.0f;
    many += (i ? ", [" : "[") + std::to_string(3.0f * std::cos(a)) + ", " + std::to_string(3.0f * std::sin(a)) + "]";
  }
  many += "]";
  const std::vector<Case> cases = {
      // The file itself.
      {"", "root", "JSON syntax error at line 1, column 1"},
      {"{\"bounds\": [0, 0, 10, 10],\n \"statics\": [\n  " + good_static + ",\n  {\"shape\": {\"type\": \"circle\", \"radius\": 1,}}]}",
       "statics[1].shape", "JSON syntax error at line 4, column"},
      {"[1, 2]", "root", "expected a scene (a JSON object), got array"},
      {static_shape(R"({"type": "circle", "radius": 1e400})"), "statics[0].shape.radius",
       "not a finite float (1e400 is beyond double range)"},
      {R"({"bounds": [0, 0, 10, 10], "statix": []})", "statix", "unknown field"},
      // Bounds and walls.
      {R"({"statics": []})", "bounds", "missing"},
      {R"({"bounds": [0, 0, 10]})", "bounds", "expected [minx, miny, maxx, maxy]"},
      {R"({"bounds": [0, 10, 10, 0]})", "bounds", "min must be < max"},
      {R"({"bounds": [0, 0, 1e39, 10]})", "bounds[2]", "not a finite float (1e+39)"},
      {scene_with(R"(, "walls": -1)"), "walls", "must be >= 0"},
      // Statics: the collider fields.
      {scene_with(R"(, "statics": {})"), "statics", "expected an array, got object"},
      {scene_with(R"(, "statics": [)" + good_static + R"(, 5])"), "statics[1]", "expected a static (a JSON object), got number"},
      {scene_with(R"(, "statics": [{"shape": {"type": "circle", "radius": 1}, "sensr": true}])"), "statics[0].sensr",
       "unknown field (expected one of: shape, shapes, transform, user_id, layer, mask, sensor, comment)"},
      {scene_with(R"(, "statics": [{"user_id": 3}])"), "statics[0].shapes", "missing"},
      {scene_with(R"(, "statics": [{"shape": {"type": "circle", "radius": 1}, "shapes": []}])"), "statics[0]",
       "not both"},
      {scene_with(R"(, "statics": [{"shapes": []}])"), "statics[0].shapes", "empty"},
      {scene_with(R"(, "statics": [{"shapes": {"type": "circle", "radius": 1}}])"), "statics[0].shapes",
       "expected an array of shapes"},
      {scene_with(R"(, "statics": [)" + good_static + ", " + good_static +
                  R"(, {"shape": {"type": "circle", "radius": 1}, "transform": {"p": [1, 2, 3]}}])"),
       "statics[2].transform.p", "3D coordinates"},
      {scene_with(R"(, "statics": [{"shape": {"type": "circle", "radius": 1}, "transform": {"angle": "90deg"}}])"),
       "statics[0].transform.angle", "expected a number, got string"},
      {scene_with(R"(, "statics": [{"shape": {"type": "circle", "radius": 1}, "transform": [0, 0]}])"),
       "statics[0].transform", "expected {\"p\": [x, y], \"angle\": radians}"},
      {scene_with(R"(, "statics": [{"shape": {"type": "circle", "radius": 1}, "user_id": -3}])"), "statics[0].user_id",
       "must be >= 0"},
      {scene_with(R"(, "statics": [{"shape": {"type": "circle", "radius": 1}, "user_id": 1.5}])"), "statics[0].user_id",
       "expected a non-negative integer"},
      {scene_with(R"(, "statics": [{"shape": {"type": "circle", "radius": 1}, "layer": 4294967296}])"),
       "statics[0].layer", "out of range"},
      {scene_with(R"(, "statics": [{"shape": {"type": "circle", "radius": 1}, "mask": "all"}])"), "statics[0].mask",
       "expected a non-negative integer, got string"},
      {scene_with(R"(, "statics": [{"shape": {"type": "circle", "radius": 1}, "sensor": 1}])"), "statics[0].sensor",
       "expected true or false"},
      // Shapes.
      {static_shape(R"({"type": "blob"})"), "statics[0].shape.type", "unknown shape type \"blob\""},
      {static_shape(R"({"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]})"),
       "statics[0].shape.type", "3D shape"},
      {static_shape(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1})"), "statics[0].shape.center",
       "3D coordinates"},
      {static_shape(R"({"radius": 1})"), "statics[0].shape.type", "missing"},
      {static_shape(R"("circle")"), "statics[0].shape", "expected a shape"},
      {static_shape(R"({"type": "circle", "radius": 1, "centre": [0, 0]})"), "statics[0].shape.centre", "unknown field"},
      {static_shape(R"({"type": "circle"})"), "statics[0].shape.radius", "missing"},
      {scene_with(R"(, "statics": [)" + good_static + ", " + good_static +
                  R"(, {"shapes": [{"type": "circle", "radius": -1}]}])"),
       "statics[2].shapes[0].radius", "negative (-1)"},
      {static_shape(R"({"type": "circle", "radius": 1, "center": [0]})"), "statics[0].shape.center",
       "expected 2 numbers, got 1"},
      {static_shape(R"({"type": "circle", "radius": 1, "center": [0, 1e39]})"), "statics[0].shape.center[1]",
       "not a finite float"},
      {static_shape(R"({"type": "capsule", "a": [1, 1], "b": [1, 1], "radius": 0.5})"), "statics[0].shape", "coincide"},
      {static_shape(R"({"type": "capsule", "a": [0, 0], "b": [1, 1]})"), "statics[0].shape.radius", "missing"},
      {static_shape(R"({"type": "segment", "a": [2, 2], "b": [2, 2]})"), "statics[0].shape", "coincide"},
      {static_shape(R"({"type": "segment", "a": [2, 2]})"), "statics[0].shape.b", "missing"},
      {static_shape(R"({"type": "box", "half": [1, 0]})"), "statics[0].shape.half", "must be > 0"},
      {static_shape(R"({"type": "box", "half": [1, 1], "radius": -0.5})"), "statics[0].shape.radius", "negative"},
      {static_shape(R"({"type": "polygon", "vertices": [[0, 0], [2, 0], [1, 0.5], [2, 2], [0, 2]]})"),
       "statics[0].shape.vertices", "polygon vertex 2: turns clockwise"},
      {static_shape(R"({"type": "polygon", "vertices": [[0, 0], [0, 2], [2, 2], [2, 0]]})"),
       "statics[0].shape.vertices", "add \"concave\": true"},
      {static_shape(R"({"type": "polygon", "vertices": [[0, 0], [1, 0]]})"), "statics[0].shape.vertices",
       "at least 3 vertices"},
      {static_shape(R"({"type": "polygon", "vertices": )" + many + "}"), "statics[0].shape.vertices",
       "more than kMaxPolygonVertices"},
      {static_shape(R"({"type": "polygon", "vertices": [[0, 0], [1, 0], [0, 1]], "radius": 1e39})"),
       "statics[0].shape.radius", "not a finite float"},
      {static_shape(R"({"type": "polygon", "vertices": [[0, 0], [1, 0], [0, "1"]]})"),
       "statics[0].shape.vertices[2][1]", "expected a number"},
      {static_shape(R"({"type": "polygon", "concave": true, "vertices": [[0, 0], [2, 2], [2, 0], [0, 2]]})"),
       "statics[0].shape.vertices", "self-intersecting"},
      {static_shape(R"({"type": "polygon", "concave": true, "vertices": [[0, 0], [1, 1], [2, 2]]})"),
       "statics[0].shape.vertices", "zero area"},
      {static_shape(R"({"type": "polygon", "concave": true, "radius": 0.1, "vertices": [[0, 0], [1, 0], [0, 1]]})"),
       "statics[0].shape.radius", "not allowed on a concave polygon"},
      {static_shape(R"({"type": "polygon", "concave": "yes", "vertices": [[0, 0], [1, 0], [0, 1]]})"),
       "statics[0].shape.concave", "expected true or false"},
      {static_shape(R"({"type": "polyline", "points": [[0, 0], [1, 1], [1, 1]]})"), "statics[0].shape.points[2]",
       "repeats statics[0].shape.points[1]"},
      {static_shape(R"({"type": "polyline", "points": [[0, 0], [1, 1], [0, 0]], "closed": true})"),
       "statics[0].shape.points[0]", "repeats statics[0].shape.points[2]"},
      {static_shape(R"({"type": "polyline", "points": [[0, 0]]})"), "statics[0].shape.points", "at least 2 points"},
      // Bodies.
      {scene_with(R"(, "bodies": [{"shape": {"type": "circle", "radius": 1}, "transform": {"p": [5, 5]}, "velocity": [1e39, 0]}])"),
       "bodies[0].velocity[0]", "not a finite float"},
      {scene_with(R"(, "bodies": [{"shape": {"type": "circle", "radius": 1}, "transform": {"p": [5, 5]}, "spin": 1}])"),
       "bodies[0].spin", "unknown field"},
      {scene_with(R"(, "bodies": [{"shape": {"type": "circle", "radius": 1}, "transform": {"p": [5, 5]}, "bullet": "true"}])"),
       "bodies[0].bullet", "expected true or false"},
      {scene_with(R"(, "bodies": [{"shape": {"type": "circle", "radius": 1}, "transform": {"p": [0.5, 5]}}])"),
       "bodies[0]", "reaches outside the bounds"},
      {scene_with(R"(, "statics": [{"shape": {"type": "box", "half": [2, 2]}, "transform": {"p": [5, 5]}}],
                     "bodies": [{"shape": {"type": "circle", "radius": 1}, "transform": {"p": [5, 7.5]}}])"),
       "bodies[0]", "starts inside statics[0] (overlap depth 0.5)"},
      // Spawn and laser.
      {scene_with(R"(, "spawn": {"seed": 3})"), "spawn.count", "missing"},
      {scene_with(R"(, "spawn": {"count": 1000001})"), "spawn.count", "out of range"},
      {scene_with(R"(, "spawn": {"count": 5, "radius": [0.5, 0.2]})"), "spawn.radius", "min > max"},
      {scene_with(R"(, "spawn": {"count": 5, "radius": [0, 0.2]})"), "spawn.radius[0]", "must be > 0"},
      {scene_with(R"(, "spawn": {"count": 5, "radius": [0.5, 3]})"), "spawn.radius[1]", "too large for the bounds"},
      {scene_with(R"(, "spawn": {"count": 5, "speed": [-1, 2]})"), "spawn.speed[0]", "must be >= 0"},
      {scene_with(R"(, "spawn": {"count": 5, "bullets": 6})"), "spawn.bullets", "out of range (6 > 5)"},
      {scene_with(R"(, "spawn": {"count": 5, "bullet_speed": 0})"), "spawn.bullet_speed", "must be > 0"},
      {scene_with(R"(, "spawn": {"count": 5, "seed": 4294967296})"), "spawn.seed", "out of range"},
      {scene_with(R"(, "laser": {"origin": [0, 0], "translation": [0, 0]})"), "laser.translation", "must not be zero"},
      {scene_with(R"(, "laser": {"translation": [1, 0]})"), "laser.origin", "missing"},
      {scene_with(R"(, "laser": {"origin": [0, 0], "translation": [1, 0], "turn": 1})"), "laser.turn", "unknown field"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of(c.text);
    const std::string head = "bad.json: " + c.path + ": ";
    EXPECT_EQ(message.rfind(head, 0), 0u) << "expected '" << head << "...' for\n" << c.text << "\ngot: " << message;
    EXPECT_NE(message.find(c.reason), std::string::npos) << "'" << c.reason << "' not in: " << message;
  }
  // A file that does not exist names itself.
  try {
    (void)load_scene_json("/nonexistent/scene.json");
    ADD_FAILURE() << "a missing file was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/scene.json: cannot be read");
  }
}

// Touching a solid static is fine; entering it is not, unless the static is a sensor or its layer
// and the body's mask keep them apart (then the world never pushes them apart either).
TEST(SceneJson, BodiesMayTouchButNotEnterTheStaticsTheyMeet) {
  const auto scene = [](const std::string& static_extra, double body_y, const std::string& body_extra = "") {
    return scene_with(R"(, "statics": [{"shape": {"type": "box", "half": [2, 2]}, "transform": {"p": [5, 5]})" +
                      static_extra + R"(}], "bodies": [{"shape": {"type": "circle", "radius": 1}, "transform": {"p": [5, )" +
                      std::to_string(body_y) + "]}" + body_extra + "}]");
  };
  EXPECT_NO_THROW((void)parse_scene_json(scene("", 8.0), "touch.json"));  // resting on the top face
  EXPECT_NE(error_of(scene("", 7.99)).find("bodies[0]: starts inside statics[0]"), std::string::npos);
  EXPECT_NO_THROW((void)parse_scene_json(scene(R"(, "sensor": true)", 6.0), "sensor.json"));
  EXPECT_NO_THROW((void)parse_scene_json(scene(R"(, "layer": 8)", 6.0, R"(, "mask": 7)"), "layers.json"));
  EXPECT_NO_THROW((void)parse_scene_json(scene("", 6.0, R"(, "sensor": true)"), "sensor_body.json"));
  EXPECT_NE(error_of(scene(R"(, "layer": 8)", 6.0, R"(, "mask": 15)")).find("starts inside statics[0]"),
            std::string::npos);
}

// Never a crash: the example file mangled at random (characters dropped, inserted, swapped for
// JSON punctuation, numbers replaced by bad values, the text cut short) either loads or throws
// InvalidInput naming the file; nothing else escapes.
TEST(SceneJson, MangledFilesAreErrorsNeverCrashes) {
  const std::string original = read_text(kScenes / "pinball.json");
  ASSERT_GT(original.size(), 1000u);
  std::mt19937 rng(12345);
  const std::vector<std::string> inserts = {"{", "}", "[", "]", ",", ":", "\"", "-", "0", "1e39", "1e400", "-1",
                                            "null", "true", "[]", "{}", "\"x\"", "1.5", "\\", "\n"};
  int loaded = 0, rejected = 0;
  for (int round = 0; round < 1500; ++round) {
    std::string text = original;
    const int edits = 1 + static_cast<int>(rng() % 3u);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = rng() % text.size();
      switch (rng() % 4u) {
        case 0: text.erase(at, 1 + rng() % 4u); break;
        case 1: text.insert(at, inserts[rng() % inserts.size()]); break;
        case 2: text.replace(at, 1, inserts[rng() % inserts.size()]); break;
        default: text.resize(at); break;
      }
      if (text.empty()) text = "{";
    }
    try {
      (void)parse_scene_json(text, "pinball.json");
      ++loaded;
    } catch (const InvalidInput& e) {
      ++rejected;
      EXPECT_EQ(std::string(e.what()).rfind("pinball.json: ", 0), 0u) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "escaped as " << typeid(e).name() << ": " << e.what() << "\n" << text;
    }
  }
  EXPECT_GT(rejected, 1000);  // most edits break something...
  EXPECT_GT(loaded, 20);      // ...but edits inside comments do not: both outcomes were exercised
  // Deep nesting does not overflow the stack: it is refused at kMaxJsonDepth, before parsing.
  EXPECT_NE(error_of(std::string(200000, '[')).find("JSON nested deeper than 256 levels"), std::string::npos);
  EXPECT_NE(error_of(R"({"bounds": [0, 0, 1, 1], "statics": [{"shape": )" + std::string(200000, '[') + "}]}")
                .find("statics[0].shape"),
            std::string::npos);
}

TEST(SceneJson, TiledJsonMapsAreToldApartFromScenes) {
  int maps = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(COLLIDE_DATA_DIR) / "tiled")) {
    if (entry.path().extension() != ".json" && entry.path().extension() != ".tmj") continue;
    EXPECT_TRUE(looks_like_tiled_json(entry.path())) << entry.path();
    ++maps;
  }
  EXPECT_GT(maps, 0);
  int scenes = 0;
  for (const auto& entry : fs::directory_iterator(kScenes)) {
    EXPECT_FALSE(looks_like_tiled_json(entry.path())) << entry.path();
    EXPECT_NO_THROW((void)load_scene_json(entry.path())) << entry.path();
    ++scenes;
  }
  EXPECT_EQ(scenes, 2);
  EXPECT_FALSE(looks_like_tiled_json("/nonexistent/map.json"));
  EXPECT_FALSE(looks_like_tiled_json(kScenes));  // a folder: not readable as a file
}

}  // namespace
}  // namespace collide
