// 3D shapes drawn as triangles (draw_shape through DebugDraw3): every triangle lies on the shape's
// surface, the triangles close it, wound outward (their signed volume, by the divergence
// theorem, is positive and near the shape's analytic volume), and levels give one triangle per
// triangle of theirs.
#include <collide/shape/draw_shape.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <vector>

namespace collide {
namespace {

/// Records triangles and segments.
struct Recorder final : DebugDraw3 {
  std::vector<std::array<Vec3, 3>> triangles;
  std::vector<std::array<Vec3, 2>> segments;
  std::map<DrawRole, int> roles;
  void draw_triangle(const Vec3& a, const Vec3& b, const Vec3& c, DrawRole role) override {
    triangles.push_back({a, b, c});
    ++roles[role];
  }
  void draw_segment(const Vec3& a, const Vec3& b, DrawRole role) override {
    segments.push_back({a, b});
    ++roles[role];
  }
  void draw_arrow(const Vec3&, const Vec3&, DrawRole role) override { ++roles[role]; }
  void draw_point(const Vec3&, DrawRole role) override { ++roles[role]; }

  /// Signed volume enclosed (positive when wound counter-clockwise seen from outside).
  [[nodiscard]] double volume() const {
    double v = 0.0;
    for (const auto& t : triangles) v += static_cast<double>(dot(t[0], cross(t[1], t[2]))) / 6.0;
    return v;
  }
  /// Each undirected edge used by exactly two triangles, once in each direction (a closed,
  /// consistently wound surface). Corners are matched by exact position.
  [[nodiscard]] bool closed() const {
    std::map<std::array<float, 6>, int> directed;
    for (const auto& t : triangles) {
      for (int k = 0; k < 3; ++k) {
        const Vec3 a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
        if (a == b) continue;  // a zero-length edge of a triangle at a pole
        ++directed[{a.x, a.y, a.z, b.x, b.y, b.z}];
      }
    }
    for (const auto& [e, count] : directed) {
      const auto back = directed.find({e[3], e[4], e[5], e[0], e[1], e[2]});
      if (count != 1 || back == directed.end() || back->second != 1) return false;
    }
    return true;
  }
};

const Transform3 kPlace{Vec3(3.0f, -2.0f, 5.0f), glm::normalize(Quat{0.8f, 0.3f, -0.4f, 0.2f})};

TEST(DrawShape3, SphereTrianglesLieOnItCloseItAndHoldItsVolume) {
  Recorder r;
  const Sphere s{Vec3(0.5f, 0.0f, -1.0f), 2.0f};
  draw_shape(r, Shape3D(s), kPlace, DrawRole::body);
  const Vec3 c = transform_point(kPlace, s.center);
  for (const auto& t : r.triangles) {
    for (const Vec3& p : t) EXPECT_NEAR(length(p - c), s.radius, 1e-4f);
  }
  EXPECT_TRUE(r.closed());
  const double exact = 4.0 / 3.0 * std::numbers::pi * 8.0;
  // Inscribed: a little under the sphere's volume, within the tessellation's 2% of the radius.
  EXPECT_LT(r.volume(), exact);
  EXPECT_GT(r.volume(), 0.9 * exact);
  EXPECT_EQ(r.roles.at(DrawRole::body), static_cast<int>(r.triangles.size()));
}

TEST(DrawShape3, CapsuleTrianglesLieOnItAndHoldItsVolume) {
  Recorder r;
  const Capsule3 cap = make_capsule(Vec3(0.0f, -1.0f, 0.0f), Vec3(0.5f, 1.5f, 0.2f), 0.7f);
  draw_shape(r, Shape3D(cap), kPlace, DrawRole::fast_body);
  const Vec3 a = transform_point(kPlace, cap.a), b = transform_point(kPlace, cap.b);
  for (const auto& t : r.triangles) {
    for (const Vec3& p : t) {
      // Distance to the core segment.
      const float u = std::clamp(dot(p - a, b - a) / dot(b - a, b - a), 0.0f, 1.0f);
      EXPECT_NEAR(length(p - (a + u * (b - a))), cap.radius, 1e-4f);
    }
  }
  EXPECT_TRUE(r.closed());
  const double rr = cap.radius, h = length(cap.b - cap.a);
  const double exact = std::numbers::pi * rr * rr * (h + 4.0 / 3.0 * rr);
  EXPECT_LT(r.volume(), exact);
  EXPECT_GT(r.volume(), 0.9 * exact);
}

TEST(DrawShape3, BoxAndHullAreTheirFacesWoundOutward) {
  Recorder box;
  draw_shape(box, Shape3D(make_box(Vec3(1.0f, 2.0f, 0.5f))), kPlace, DrawRole::body);
  EXPECT_EQ(box.triangles.size(), 12u);
  EXPECT_TRUE(box.closed());
  EXPECT_NEAR(box.volume(), 8.0, 1e-3);

  // A hull: a cube with a cut corner; its drawn volume is its own.
  std::vector<Vec3> points;
  for (int i = 0; i < 8; ++i) {
    if (i == 7) continue;
    points.push_back({(i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f});
  }
  points.push_back({1.0f, 1.0f, 0.0f});
  points.push_back({0.0f, 1.0f, 1.0f});
  points.push_back({1.0f, 0.0f, 1.0f});
  const ConvexHull hull = make_convex_hull(points);
  Recorder h;
  draw_shape(h, Shape3D(hull), kPlace, DrawRole::shape_a);
  EXPECT_TRUE(h.closed());
  EXPECT_NEAR(h.volume(), hull.volume, 1e-3 * hull.volume);
}

TEST(DrawShape3, ASegmentIsOneSegmentAndLevelsAreTheirTriangles) {
  Recorder seg;
  draw_shape(seg, Shape3D(Segment3{Vec3(0.0f), Vec3(1.0f, 2.0f, 3.0f)}), kPlace, DrawRole::path);
  ASSERT_EQ(seg.segments.size(), 1u);
  EXPECT_NEAR(length(seg.segments[0][1] - transform_point(kPlace, Vec3(1.0f, 2.0f, 3.0f))), 0.0f, 1e-5f);
  EXPECT_TRUE(seg.triangles.empty());

  const std::vector<Vec3> v{{0, 0, 0}, {4, 0, 0}, {4, 0, 4}, {0, 1, 4}, {2, 3, 2}};
  const std::vector<glm::uvec3> t{{0, 2, 1}, {0, 3, 2}, {0, 1, 4}};
  const TriangleMesh mesh = make_triangle_mesh(v, t);
  Recorder m;
  draw_shape(m, mesh, kPlace, DrawRole::static_geometry);
  ASSERT_EQ(m.triangles.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(length(m.triangles[i][static_cast<std::size_t>(k)] - transform_point(kPlace, v[t[i][k]])), 0.0f, 1e-4f);
    }
  }

  // A height field of 4 x 3 samples: 3 x 2 cells, two triangles each.
  std::vector<float> heights(12, 0.5f);
  heights[5] = 1.5f;
  HeightField field = make_height_field(4, 3, heights, Vec2(1.0f), Vec3(0.0f));
  Recorder f;
  draw_shape(f, field, kPlace, DrawRole::static_geometry);
  EXPECT_EQ(f.triangles.size(), 12u);
  for (const auto& tri : f.triangles) {
    for (const Vec3& p : tri) {
      const Vec3 local = inv_transform_point(kPlace, p);
      EXPECT_GE(local.y, 0.5f - 1e-4f);
      EXPECT_LE(local.y, 1.5f + 1e-4f);
    }
  }
}

}  // namespace
}  // namespace collide
