// The shared JSON vocabulary (collide/io/shape_json.hpp): shapes read equal the library's make_*
// results, every rejection is a JsonFieldError naming its path in one notation, unknown fields
// are named in both entry points, 3D transforms are parsed (quaternions normalised or rejected),
// and JSON text is read safely (depth limit, numbers beyond double range, positions of syntax
// errors as nlohmann's own, valid UTF-8 messages).

#include <collide/io/shape_json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <variant>
#include <vector>

namespace collide {
namespace {

using nlohmann::json;

/// The JsonFieldError `f` throws: "path|reason", or "no error".
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const JsonFieldError& e) {
    EXPECT_EQ(std::string(e.what()), (e.path().empty() ? std::string("root") : e.path()) + ": " + e.reason());
    return e.path() + "|" + e.reason();
  }
  return "no error";
}

std::string shape_error(const std::string& text) {
  const JsonPath root;
  return error_of([&] { (void)shape_from_json(json::parse(text), root.member("a")); });
}

std::string pieces_error(const std::string& text) {
  const JsonPath root;
  std::vector<Shape2D> out;
  const JsonPath statics = root.member("statics");
  const JsonPath second = statics.element(2);
  return error_of([&] { shape_pieces_from_json(json::parse(text), second.member("shape"), out); });
}

bool same_polygon(const Polygon& a, const Polygon& b) {
  if (a.count != b.count || a.radius != b.radius) return false;
  for (int i = 0; i < a.count; ++i) {
    if (a.vertices[i] != b.vertices[i] || a.normals[i] != b.normals[i]) return false;
  }
  return true;
}

template <class P>
concept StepsFromATemporary = requires { P().member("a"); } || requires { P().element(0); };

TEST(JsonPath, WritesMembersWithDotsAndElementsInBrackets) {
  const JsonPath root;
  EXPECT_EQ(root.str(), "");
  const JsonPath statics = root.member("statics");
  const JsonPath second = statics.element(2);
  const JsonPath shapes = second.member("shapes");
  const JsonPath shape = shapes.element(0);
  EXPECT_EQ(shape.member("radius").str(), "statics[2].shapes[0].radius");
  const JsonPath a = root.member("a");
  const JsonPath vertices = a.member("vertices");
  const JsonPath v3 = vertices.element(3);
  EXPECT_EQ(v3.element(1).str(), "a.vertices[3][1]");
  const JsonPath first = root.element(0);
  EXPECT_EQ(first.element(1).str(), "[0][1]");
  // root.member("a").member("b") does not compile: the middle step would be a dead temporary.
  static_assert(!StepsFromATemporary<JsonPath>);
  EXPECT_EQ(std::string(JsonFieldError("", "why").what()), "root: why");
  EXPECT_EQ(std::string(JsonFieldError("a.b", "why").what()), "a.b: why");
}

// Both entry points build exactly what the make_* functions build from the same numbers.
TEST(ShapeJson, ShapesAreWhatTheLibraryBuildsFromTheSameNumbers) {
  const JsonPath root;
  const auto convex = [&](const std::string& text) {
    const AnyShape s = shape_from_json(json::parse(text), root.member("a"));
    EXPECT_EQ(dimension_of(s), JsonDimension::two);
    std::vector<Shape2D> pieces;
    shape_pieces_from_json(json::parse(text), root.member("a"), pieces);
    EXPECT_EQ(pieces.size(), 1u) << text;
    return std::pair{std::get<Shape2D>(s), pieces.at(0)};
  };
  for (const char* name : {"circle", "sphere"}) {  // one type, two names; no center: the caller's 2D
    const auto [c, p] = convex(std::string(R"({"type": ")") + name + R"(", "center": [1.5, -2], "radius": 0.25})");
    const Circle want = make_circle({1.5f, -2.0f}, 0.25f);
    for (const Shape2D& s : {c, p}) {
      ASSERT_TRUE(std::holds_alternative<Circle>(s));
      EXPECT_EQ(std::get<Circle>(s).center, want.center);
      EXPECT_EQ(std::get<Circle>(s).radius, want.radius);
    }
    EXPECT_EQ(std::get<Circle>(convex(std::string(R"({"type": ")") + name + R"(", "radius": 2})").first).center,
              Vec2(0.0f, 0.0f));
  }
  {
    const auto [c, p] = convex(R"({"type": "capsule", "a": [0, 1], "b": [3, 4], "radius": 0.5})");
    for (const Shape2D& s : {c, p}) {
      EXPECT_EQ(std::get<Capsule>(s).a, Vec2(0.0f, 1.0f));
      EXPECT_EQ(std::get<Capsule>(s).b, Vec2(3.0f, 4.0f));
      EXPECT_EQ(std::get<Capsule>(s).radius, 0.5f);
    }
  }
  {
    const auto [c, p] = convex(R"({"type": "segment", "a": [-1, 0], "b": [2, 0.1]})");
    for (const Shape2D& s : {c, p}) EXPECT_EQ(std::get<Segment>(s).b, Vec2(2.0f, 0.1f));
  }
  {
    const auto [c, p] = convex(R"({"type": "box", "half": [2, 0.5], "radius": 0.1})");
    const Polygon want = make_box({2.0f, 0.5f}, 0.1f);
    for (const Shape2D& s : {c, p}) EXPECT_TRUE(same_polygon(std::get<Polygon>(s), want));
  }
  {
    const auto [c, p] = convex(R"({"type": "polygon", "vertices": [[0, 0], [4, 0], [5, 2], [0, 3]], "radius": 0.2})");
    const std::vector<Vec2> v = {{0, 0}, {4, 0}, {5, 2}, {0, 3}};
    const Polygon want = make_convex_polygon(v, 0.2f);
    for (const Shape2D& s : {c, p}) EXPECT_TRUE(same_polygon(std::get<Polygon>(s), want));
  }
}

TEST(ShapeJson, PiecesOfPolylinesAndConcavePolygons) {
  std::vector<Shape2D> out;
  const JsonPath root;
  shape_pieces_from_json(json::parse(R"({"type": "polyline", "points": [[0, 0], [1, 0], [1, 1]], "closed": true})"),
                         root, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(std::get<Segment>(out[2]).a, Vec2(1.0f, 1.0f));
  EXPECT_EQ(std::get<Segment>(out[2]).b, Vec2(0.0f, 0.0f));
  out.clear();
  shape_pieces_from_json(
      json::parse(R"({"type": "polygon", "concave": true, "vertices": [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]})"),
      root, out);
  EXPECT_EQ(out.size(), 2u);  // an L: two convex pieces
  out.clear();
  shape_pieces_from_json(json::parse(R"({"type": "polygon", "concave": false, "vertices": [[0, 0], [1, 0], [0, 1]]})"),
                         root, out);
  EXPECT_EQ(out.size(), 1u);
}

// The same rejection reads the same in both entry points, named by one path notation.
TEST(ShapeJson, RejectionsNameTheFieldTheSameWayInBothEntryPoints) {
  struct Case {
    std::string text, field, reason;
  };
  const std::vector<Case> cases = {
      {R"({"type": "circle", "radius": 1, "centre": [0, 0]})", "centre",
       "unknown field (expected one of: type, center, radius, comment)"},
      {R"({"type": "circle", "radius": -1})", "radius", "negative (-1)"},
      {R"({"type": "circle", "radius": 1e39})", "radius", "not a finite float (1e+39)"},
      {R"({"type": "circle", "radius": "1"})", "radius", "expected a number, got string"},
      {R"({"type": "circle"})", "radius", "missing"},
      {R"({"type": "circle", "radius": 1, "center": [0]})", "center", "expected 2 numbers, got 1"},
      {R"({"type": "capsule", "a": [1, 1], "b": [1, 1], "radius": 0.5})", "", "capsule: a and b coincide (use a circle)"},
      {R"({"type": "capsule", "a": [0, 0], "b": [1, 0, 2], "radius": 0.5})", "b",
       "expected 2 numbers, got 3 (3D coordinates where 2D is expected)"},
      {R"({"type": "segment", "a": [0, 0]})", "b", "missing"},
      {R"({"type": "box", "half": [1, 0]})", "half", "half extents must be > 0"},
      {R"({"type": "polygon", "vertices": [[0, 0], [1, 0], [0, "1"]]})", "vertices[2][1]", "expected a number, got string"},
      {R"({"type": "polygon", "vertices": {}})", "vertices", "expected an array of [x, y] points, got object"},
      {R"({"type": 3})", "type", "expected a string, got number"},
      {R"({"radius": 1})", "type", "missing"},
      {R"([1, 2])", "", "expected a shape (a JSON object), got array"},
  };
  for (const Case& c : cases) {
    const std::string a = c.field.empty() ? "a" : "a." + c.field;
    const std::string s = "statics[2].shape" + (c.field.empty() ? "" : "." + c.field);
    EXPECT_EQ(shape_error(c.text), a + "|" + c.reason) << c.text;
    EXPECT_EQ(pieces_error(c.text), s + "|" + c.reason) << c.text;
  }
  // Comments are allowed in every object.
  EXPECT_EQ(shape_error(R"({"type": "circle", "radius": 1, "comment": {"any": ["value"]}})"), "no error");
  EXPECT_EQ(pieces_error(R"({"type": "polyline", "points": [[0, 0], [1, 0]], "comment": 1})"), "no error");
  // Where the two differ, they differ on purpose: pieces take concave outlines and polylines.
  EXPECT_EQ(shape_error(R"({"type": "polygon", "vertices": [[0, 0], [0, 1], [1, 0]]})"),
            "a.vertices|polygon vertex 0: turns clockwise (polygon must be convex and counter-clockwise)");
  EXPECT_EQ(pieces_error(R"({"type": "polygon", "vertices": [[0, 0], [0, 1], [1, 0]]})"),
            "statics[2].shape.vertices|polygon vertex 0: turns clockwise (polygon must be convex and "
            "counter-clockwise); for a concave or clockwise outline add \"concave\": true");
  EXPECT_EQ(shape_error(R"({"type": "polyline", "points": [[0, 0], [1, 0]]})"),
            "a.type|a polyline is several convex pieces; one convex shape is expected here");
  EXPECT_EQ(pieces_error(R"({"type": "polygon", "concave": true, "vertices": [[0, 0], [2, 2], [2, 0], [0, 2]]})")
                .rfind("statics[2].shape.vertices|polygon is self-intersecting", 0),
            0u);
}

// 3D: the dimension is told by the coordinates (or the type); 3D shapes are the library's own
// make_* results, and the pieces of a scene are 2D.
TEST(ShapeJson, ThreeDimensionalShapesAreToldByTheirCoordinatesAndBuiltByTheLibrary) {
  const JsonPath root;
  const auto shape3 = [&](const std::string& text, JsonDimension untold = JsonDimension::two) {
    const AnyShape s = shape_from_json(json::parse(text), root.member("a"), untold);
    EXPECT_EQ(dimension_of(s), JsonDimension::three) << text;
    return s;
  };
  for (const char* name : {"sphere", "circle"}) {  // one type, two names; 3 numbers: a sphere
    const AnyShape s = shape3(std::string(R"({"type": ")") + name + R"(", "center": [1, 2, 3], "radius": 0.5})");
    const Sphere& sphere = std::get<Sphere>(std::get<Shape3D>(s));
    EXPECT_EQ(sphere.center, Vec3(1.0f, 2.0f, 3.0f));
    EXPECT_EQ(sphere.radius, 0.5f);
    EXPECT_STREQ(type_name(s), "sphere");
  }
  {
    const AnyShape s = shape3(R"({"type": "capsule", "a": [0, 0, 0], "b": [1, 0, 0], "radius": 1})");
    EXPECT_EQ(std::get<Capsule3>(std::get<Shape3D>(s)).b, Vec3(1.0f, 0.0f, 0.0f));
  }
  {
    const AnyShape s = shape3(R"({"type": "segment", "a": [0, 0, 0], "b": [0, 0, 2]})");
    EXPECT_EQ(std::get<Segment3>(std::get<Shape3D>(s)).b, Vec3(0.0f, 0.0f, 2.0f));
  }
  {
    const AnyShape s = shape3(R"({"type": "box", "half": [1, 2, 3], "radius": 0.25})");
    EXPECT_EQ(std::get<Box>(std::get<Shape3D>(s)).half, Vec3(1.0f, 2.0f, 3.0f));
    EXPECT_EQ(std::get<Box>(std::get<Shape3D>(s)).radius, 0.25f);
  }
  {
    // A cube's corners and its centre: the hull is the cube (8 vertices, 6 faces).
    const AnyShape s = shape3(R"({"type": "hull", "points": [[0, 0, 0], [-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], "radius": 0.1})");
    const ConvexHull& hull = std::get<ConvexHull>(std::get<Shape3D>(s));
    EXPECT_EQ(hull.vertex_count(), 8);
    EXPECT_EQ(hull.faces.size(), 6u);
    EXPECT_EQ(hull.radius, 0.1f);
    EXPECT_STREQ(type_name(s), "hull");
  }
  {
    const AnyShape s = shape3(R"({"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]})");
    EXPECT_EQ(std::get<Triangle>(s).vertices[2], Vec3(0.0f, 1.0f, 0.0f));
    EXPECT_STREQ(type_name(s), "triangle");
  }
  // Without coordinates: a sphere takes the caller's dimension, a circle is 2D.
  const AnyShape untold = shape3(R"({"type": "sphere", "radius": 1})", JsonDimension::three);
  EXPECT_EQ(std::get<Sphere>(std::get<Shape3D>(untold)).center, Vec3(0.0f));
  EXPECT_EQ(dimension_of(shape_from_json(json::parse(R"({"type": "circle", "radius": 1})"), root.member("a"),
                                         JsonDimension::three)),
            JsonDimension::two);
  // The cues: what a shape or transform tells of its dimension before it is read.
  const auto cue = [](const char* text) {
    const auto c = shape_dimension_cue(json::parse(text));
    return c ? std::to_string(static_cast<int>(c->dimension)) + std::string(c->field) : std::string("none");
  };
  EXPECT_EQ(cue(R"({"type": "sphere", "radius": 1})"), "none");
  EXPECT_EQ(cue(R"({"type": "circle", "radius": 1})"), "2type");
  EXPECT_EQ(cue(R"({"type": "circle", "center": [0, 0, 0], "radius": 1})"), "3center");
  EXPECT_EQ(cue(R"({"type": "capsule", "a": [0, 0], "b": [1, 0, 0]})"), "2a");
  EXPECT_EQ(cue(R"({"type": "box", "half": [1, 1, 1, 1]})"), "none");
  EXPECT_EQ(cue(R"({"type": "hull"})"), "3type");
  EXPECT_EQ(cue(R"({"type": "polygon"})"), "2type");
  EXPECT_EQ(cue(R"({"type": "blob", "center": [0, 0]})"), "none");
  EXPECT_EQ(cue(R"([1, 2, 3])"), "none");
  const auto tcue = [](const char* text) {
    const auto c = transform_dimension_cue(json::parse(text));
    return c ? std::to_string(static_cast<int>(c->dimension)) + std::string(c->field) : std::string("none");
  };
  EXPECT_EQ(tcue(R"({"p": [0, 0], "q": [1, 0, 0, 0]})"), "3q");
  EXPECT_EQ(tcue(R"({"p": [0, 0, 0], "angle": 1})"), "2angle");
  EXPECT_EQ(tcue(R"({"p": [0, 0, 0]})"), "3p");
  EXPECT_EQ(tcue(R"({})"), "none");
  EXPECT_EQ(tcue(R"(7)"), "none");
  EXPECT_EQ(pieces_error(R"({"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]})"),
            "statics[2].shape.type|\"hull\" is a 3D shape; only 2D shapes are accepted here");
  EXPECT_EQ(pieces_error(R"({"type": "box", "half": [1, 1, 1]})"),
            "statics[2].shape.half|3D coordinates; only 2D shapes are accepted here");
  EXPECT_EQ(shape_error(R"({"type": "polygon", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]})"),
            "a.vertices[0]|expected 2 numbers, got 3 (3D coordinates where 2D is expected)");
  EXPECT_EQ(shape_error(R"({"type": "blob"})"),
            "a.type|unknown shape type \"blob\" (expected circle, sphere, capsule, box, polygon, segment, hull or "
            "triangle)");
}

TEST(TransformJson, TwoDimensionalTransforms) {
  const JsonPath root;
  const JsonPath x = root.member("x");
  const Transform t = transform_from_json(json::parse(R"({"p": [1, 2], "angle": 0.5})"), x);
  EXPECT_EQ(t.p, Vec2(1.0f, 2.0f));
  EXPECT_EQ(t.q.c, std::cos(0.5f));
  EXPECT_EQ(t.q.s, std::sin(0.5f));
  const Transform id = transform_from_json(json::parse(R"({"comment": "identity"})"), x);
  EXPECT_EQ(id.p, Vec2(0.0f, 0.0f));
  EXPECT_EQ(id.q.c, 1.0f);
  EXPECT_EQ(id.q.s, 0.0f);
  const auto err = [&](const char* text) { return error_of([&] { (void)transform_from_json(json::parse(text), x); }); };
  EXPECT_EQ(err(R"({"p": [1, 2], "spin": 1})"), "x.spin|unknown field (expected one of: p, angle, comment)");
  EXPECT_EQ(err(R"({"p": [1, 2, 3]})"), "x.p|expected 2 numbers, got 3 (3D coordinates where 2D is expected)");
  EXPECT_EQ(err(R"({"q": [1, 0, 0, 0]})"),
            "x.q|a quaternion is a 3D rotation where a 2D transform is expected (\"angle\": radians)");
  EXPECT_EQ(error_of([&] { (void)transform_from_json(parse_json(R"({"angle": 1e400})"), x); }),
            "x.angle|not a finite float (1e400 is beyond double range)");
  EXPECT_EQ(err("[0, 0]"), "x|expected {\"p\": [x, y], \"angle\": radians}, got array");
}

// q = [w, x, y, z]: normalised within kJsonUnitQuaternionTolerance of unit length, rejected
// beyond; rotations checked against the axis-angle formula (Rodrigues) in double.
TEST(TransformJson, ThreeDimensionalTransformsNormaliseNearlyUnitQuaternions) {
  const JsonPath root;
  const JsonPath x = root.member("xa");
  const Transform3 id = transform3_from_json(json::parse("{}"), x);
  EXPECT_EQ(id.p, Vec3(0.0f));
  EXPECT_EQ(id.q, Quat(1.0f, 0.0f, 0.0f, 0.0f));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int accepted = 0, rejected = 0;
  for (int i = 0; i < 400; ++i) {
    double axis[3] = {u(rng), u(rng), u(rng)};
    const double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    if (n < 1e-3) continue;
    for (double& a : axis) a /= n;
    const double angle = 3.0 * u(rng);
    const double scale = 1.0 + 2e-3 * u(rng);  // within the tolerance about half the time
    const double q[4] = {scale * std::cos(angle / 2), scale * std::sin(angle / 2) * axis[0],
                         scale * std::sin(angle / 2) * axis[1], scale * std::sin(angle / 2) * axis[2]};
    json j = {{"p", {1.0, -2.0, 3.5}}, {"q", {q[0], q[1], q[2], q[3]}}};
    const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (std::fabs(length - 1.0) > kJsonUnitQuaternionTolerance * 1.0001) {
      EXPECT_EQ(error_of([&] { (void)transform3_from_json(j, x); }).rfind("xa.q|not a unit quaternion (length ", 0), 0u);
      ++rejected;
      continue;
    }
    if (std::fabs(length - 1.0) > kJsonUnitQuaternionTolerance * 0.9999) continue;  // too close to call in float
    const Transform3 t = transform3_from_json(j, x);
    ++accepted;
    EXPECT_NEAR(glm::length(t.q), 1.0f, 1e-6f);
    EXPECT_EQ(t.p, Vec3(1.0f, -2.0f, 3.5f));
    // Rodrigues: v cos + (k x v) sin + k (k . v)(1 - cos), for v = (0.3, -1, 2).
    const double v[3] = {0.3, -1.0, 2.0};
    const double c = std::cos(angle), s = std::sin(angle);
    const double kv = axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2];
    const double kxv[3] = {axis[1] * v[2] - axis[2] * v[1], axis[2] * v[0] - axis[0] * v[2],
                           axis[0] * v[1] - axis[1] * v[0]};
    const Vec3 got = transform_point(t, Vec3(0.3f, -1.0f, 2.0f));
    for (int k = 0; k < 3; ++k) {
      const double want = v[k] * c + kxv[k] * s + axis[k] * kv * (1 - c) + (k == 0 ? 1.0 : k == 1 ? -2.0 : 3.5);
      EXPECT_NEAR(got[k], want, 1e-5);
    }
  }
  EXPECT_GT(accepted, 100);  // both outcomes exercised
  EXPECT_GT(rejected, 100);
  const auto err = [&](const char* text) { return error_of([&] { (void)transform3_from_json(json::parse(text), x); }); };
  EXPECT_EQ(err(R"({"q": [1.0011, 0, 0, 0]})"), "xa.q|not a unit quaternion (length 1.0011; must be within 0.001 of 1)");
  EXPECT_EQ(err(R"({"q": [0.9989, 0, 0, 0]})"), "xa.q|not a unit quaternion (length 0.9989; must be within 0.001 of 1)");
  EXPECT_EQ(err(R"({"q": [0, 0, 0, 0]})"), "xa.q|not a unit quaternion (length 0; must be within 0.001 of 1)");
  EXPECT_EQ(err(R"({"q": [1, 0, 0]})"), "xa.q|expected 4 numbers [w, x, y, z], got 3");
  EXPECT_EQ(err(R"({"q": [1, 0, 0, 1e39]})"), "xa.q[3]|not a finite float (1e+39)");
  EXPECT_EQ(err(R"({"p": [1, 2]})"), "xa.p|expected 3 numbers, got 2 (2D coordinates where 3D is expected)");
  EXPECT_EQ(err(R"({"angle": 1})"),
            "xa.angle|an angle is a 2D rotation where a 3D transform is expected (\"q\": [w, x, y, z])");
  EXPECT_EQ(err(R"({"p": [0, 0, 0], "scale": 2})"), "xa.scale|unknown field (expected one of: p, q, comment)");
  // Exactly unit stays exactly as written.
  EXPECT_EQ(transform3_from_json(json::parse(R"({"q": [0, 1, 0, 0]})"), x).q, Quat(0.0f, 1.0f, 0.0f, 0.0f));
}

TEST(ParseJson, NumbersBeyondDoubleRangeAreNamedByTheirField) {
  const json j = parse_json(R"({"a": {"type": "circle", "radius": -1e400}, "s": "1e400", "n": 1e-400})");
  const JsonPath root;
  EXPECT_EQ(error_of([&] { (void)shape_from_json(j["a"], root.member("a")); }),
            "a.radius|not a finite float (-1e400 is beyond double range)");
  EXPECT_EQ(j["s"], "1e400");  // a string that looks like one is left alone
  EXPECT_EQ(j["n"], 0.0);      // underflow is an ordinary 0
  EXPECT_EQ(error_of([&] { (void)string_from_json(j["a"]["radius"], root.member("t")); }),
            "t|expected a string, got a number beyond double range (-1e400)");
  // Only well-formed numbers are marked: a malformed one stays a syntax error.
  for (const char* bad : {"[1e400.5]", "[01e400]", "[1e400e1]", "[-1e400-]", "[1e+400x]"}) {
    EXPECT_NE(error_of([&] { (void)parse_json(bad); }).find("|JSON syntax error at line 1, column "), std::string::npos)
        << bad;
  }
  EXPECT_EQ(parse_json("[1e400, -2E+999]").dump(), "[\"\\u0001beyond double range: 1e400\",\"\\u0001beyond double range: -2E+999\"]");
}

TEST(ParseJson, NestingIsLimitedBeforeParsing) {
  const auto nested = [](std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); };
  EXPECT_NO_THROW((void)parse_json(nested(kMaxJsonDepth)));
  EXPECT_EQ(error_of([&] { (void)parse_json(nested(kMaxJsonDepth + 1)); }),
            "[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]...|JSON nested deeper than 256 levels (the limit) at "
            "line 1, column 257");
  EXPECT_EQ(error_of([&] { (void)parse_json(R"({"a": {"b": )" + nested(kMaxJsonDepth) + "}}"); }).substr(0, 9),
            "a.b[0][0]");
  EXPECT_NO_THROW((void)parse_json(R"({"a": "[[[[[[\"[[[[[", "b": )" + nested(kMaxJsonDepth - 1) + "}"));
  EXPECT_NE(error_of([&] { (void)parse_json(std::string(1000000, '{')); }).find("|JSON nested deeper than 256"),
            std::string::npos);
}

/// "at line L, column C" of nlohmann's own parse error for `text` ("" when it parses).
std::string nlohmann_position(const std::string& text) {
  try {
    const json ignored = json::parse(text);
  } catch (const json::parse_error& e) {
    const std::string what = e.what();
    const std::size_t at = what.find("at line ");
    return what.substr(at, what.find(": ", at) - at);
  }
  return {};
}

// Positions of syntax errors are nlohmann's own (the oracle), also when numbers beyond double
// range were marked (the marked text is longer: its positions are mapped back).
TEST(ParseJson, SyntaxErrorsGiveNlohmannsPositionAndThePathBeingRead) {
  for (const std::string text : {std::string("{not json"), std::string(R"({"a": 1 "b": 2})"),
                                 std::string("{\"bounds\": [0, 0],\n \"x\": [1,\n  2 3]}"), std::string(""),
                                 std::string("[1, 2"), std::string("{\"a\": [1, 2, }")}) {
    const std::string want = nlohmann_position(text);
    ASSERT_FALSE(want.empty());
    const std::string got = error_of([&] { (void)parse_json(text); });
    EXPECT_NE(got.find("|JSON syntax error " + want + ": "), std::string::npos) << got;
    // The same text with a number beyond double range in front, against one of the same length.
    if (text.starts_with("{\"a\": ")) {
      std::string same_length = text, marked = text;
      same_length.insert(6, "10000, \"z\": ");
      marked.insert(6, "1e400, \"z\": ");
      const std::string marked_got = error_of([&] { (void)parse_json(marked); });
      EXPECT_NE(marked_got.find("|JSON syntax error " + nlohmann_position(same_length) + ": "), std::string::npos)
          << marked << " -> " << marked_got;
    }
  }
  EXPECT_EQ(error_of([&] { (void)parse_json("{\"bounds\": [0, 0],\n \"x\": [1,\n  2 3]}"); }).substr(0, 5), "x[2]|");
  EXPECT_EQ(error_of([&] { (void)parse_json(""); }).substr(0, 1), "|");  // the root
}

// Found by fuzz_query_line: a member name holding NUL ("\u0000") went into the path raw, and
// what() (a C string) ended there: the query answered {"error": ""}. Control characters in
// member names are written as JSON escapes them, and so are quoted names in reasons.
TEST(ParseJson, ControlCharactersInNamesAreEscapedInPathsAndMessages) {
  const std::string syntax = error_of([&] { (void)parse_json("{\"\\u0000e\"ansba}"); });
  EXPECT_EQ(syntax.rfind("\\u0000e|JSON syntax error at line 1, column ", 0), 0u) << syntax;
  const JsonPath root;
  const json shape = parse_json(R"({"type": "circle", "radius": 1, "\u0001\u001f\u007f": 1})");
  EXPECT_EQ(error_of([&] { (void)shape_from_json(shape, root.member("a")); }),
            "a.\\u0001\\u001f\\u007f|unknown field (expected one of: type, center, radius, comment)");
  const std::string type = error_of([&] { (void)shape_from_json(parse_json(R"({"type": "x\u0000y"})"), root); });
  EXPECT_EQ(type.rfind("type|unknown shape type \"x\\u0000y\" (expected ", 0), 0u) << type;
  try {
    (void)shape_from_json(shape, root.member("a"));
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "a.\\u0001\\u001f\\u007f: unknown field (expected one of: type, center, radius, comment)");
  }
}

TEST(ParseJson, SyntaxErrorMessagesAreValidUtf8) {
  for (const std::string bad : {"\xff", "\xc3(", "\xe2\x82", "\xed\xa0\x80", "\xc0\xaf", "\xf8\x88\x80\x80\x80"}) {
    const std::string text = "{\"k\": \"" + bad + "\"}";
    std::string message;
    try {
      (void)parse_json(text);
    } catch (const JsonFieldError& e) {
      message = e.what();
    }
    ASSERT_FALSE(message.empty());
    EXPECT_NO_THROW((void)json(message).dump()) << message;  // dump throws on bytes that are not UTF-8
    EXPECT_NE(message.find("\\x"), std::string::npos) << message;
  }
  // Valid UTF-8 is kept as it is.
  try {
    (void)parse_json("{\"k\": \"h\xc3\xa9llo \xe2\x98\x83\" x}");
  } catch (const JsonFieldError& e) {
    EXPECT_EQ(std::string(e.what()).find("\\x"), std::string::npos) << e.what();
  }
}

TEST(JsonFields, CheckFieldsAllowsCommentAndNamesTheUnknownKey) {
  const JsonPath root;
  const json j = json::parse(R"({"a": 1, "comment": "free", "zz": 2})");
  EXPECT_EQ(error_of([&] { check_fields(j, root.member("o"), {"a", "b"}); }),
            "o.zz|unknown field (expected one of: a, b, comment)");
  EXPECT_EQ(error_of([&] { check_fields(j, root, {"a", "zz"}); }), "no error");
  EXPECT_EQ(error_of([&] { (void)bool_from_json(json(1), root.member("f")); }), "f|expected true or false, got number");
  EXPECT_EQ(error_of([&] { (void)require_member(j, root, "b"); }), "b|missing");
  EXPECT_EQ(find_member(json::array(), "a"), nullptr);
}

}  // namespace
}  // namespace collide
