// make_compound_body / make_compound_static (world/compound.hpp): a decomposed concave mesh as
// one World3D body. The body's pieces sit exactly where the placement puts the hulls, the body
// turns about the hulls' volume centroid, and the world meets the concave shape, not its hull:
// a post between the dumbbell's two boxes is touched only by the bar, a ray through the gap
// misses. Checked against the hulls themselves (mapped by the placement) and the mesh's
// dimensions.
#include <collide/ccd/raycast.hpp>
#include <collide/core/error.hpp>
#include <collide/decompose/approximate_decomposition.hpp>
#include <collide/world/compound.hpp>

#include <gtest/gtest.h>

#include "support/box_meshes.hpp"
#include "support/test_util.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace collide {
namespace {

/// The dumbbell, mesh space: two 1 m cubes [0, 1]^3 and [4, 5] x [0, 1]^2, 3 m apart, joined by a
/// 0.2 m square bar along x through y, z in [0.4, 0.6].
struct Dumbbell {
  std::vector<Vec3> vertices;
  std::vector<glm::uvec3> triangles;
  std::vector<ConvexHull> hulls;  ///< decompose_approximate's, default options
};

const Dumbbell& dumbbell() {
  static const Dumbbell d = [] {
    Dumbbell out;
    test::add_dumbbell(out.vertices, out.triangles);
    out.hulls = decompose_approximate(make_triangle_mesh(out.vertices, out.triangles)).hulls;
    return out;
  }();
  return d;
}

/// Sum of volume * centroid over the volume of `shapes` (hulls) placed by `xf`, world space.
Vec3 world_centroid(std::span<const Shape3D> shapes, const Transform3& xf) {
  double volume = 0.0;
  glm::dvec3 moment(0.0);
  for (const Shape3D& s : shapes) {
    const ConvexHull& h = std::get<ConvexHull>(s);
    volume += double(h.volume);
    moment += double(h.volume) * glm::dvec3(transform_point(xf, h.centroid));
  }
  return Vec3(moment / volume);
}

TEST(CompoundBody, PiecesSitWhereThePlacementPutsTheHulls) {
  const std::vector<ConvexHull>& hulls = dumbbell().hulls;
  ASSERT_GE(hulls.size(), 3u);  // the boxes and the bar at least
  const Transform3 placement = Transform3::from_axis_angle({10.0f, -3.0f, 7.0f}, glm::normalize(Vec3(1.0f, 2.0f, 3.0f)), 0.9f);
  const BodyDef3 def = make_compound_body(hulls, placement);
  ASSERT_EQ(def.shapes.size(), hulls.size());

  // The body's origin is the hulls' volume centroid: by symmetry the middle of the bar (the
  // hulls reach outside the mesh by up to about a voxel, not symmetrically).
  const Vec3 c = compound_centroid(hulls);
  EXPECT_VEC3_NEAR(c, Vec3(2.5f, 0.5f, 0.5f), 0.05f);
  EXPECT_VEC3_NEAR(def.transform.p, transform_point(placement, c), 1e-5f);
  EXPECT_NEAR(std::fabs(glm::dot(def.transform.q, placement.q)), 1.0f, 1e-6f);
  std::vector<ConvexHull> local;
  for (std::size_t i = 0; i < hulls.size(); ++i) {
    ASSERT_TRUE(std::holds_alternative<ConvexHull>(def.shapes[i]));
    const ConvexHull& piece = std::get<ConvexHull>(def.shapes[i]);
    local.push_back(piece);
    EXPECT_EQ(piece.radius, hulls[i].radius);
    EXPECT_NEAR(piece.volume, hulls[i].volume, 1e-5f * hulls[i].volume);
    ASSERT_EQ(piece.vertex_count(), hulls[i].vertex_count()) << "hull " << i;
    for (int k = 0; k < piece.vertex_count(); ++k) {
      EXPECT_VEC3_NEAR(transform_point(def.transform, piece.vertices[k]), transform_point(placement, hulls[i].vertices[k]), 2e-5f);
    }
  }
  EXPECT_VEC3_NEAR(compound_centroid(local), Vec3(0.0f), 1e-5f);

  // In a world the body keeps its pieces, and turns about its centre of volume: the hulls'
  // centroid stays where the placement put it.
  World3D world;
  BodyDef3 spinning = def;
  spinning.angular_velocity = Vec3(0.3f, -1.1f, 0.7f);
  const BodyId id = world.add_body(spinning);
  ASSERT_EQ(world.shapes(id).size(), hulls.size());
  for (int i = 0; i < 20; ++i) {
    world.step(1.0f / 10.0f);
    EXPECT_VEC3_NEAR(world_centroid(world.shapes(id), world.transform(id)), transform_point(placement, c), 1e-4f);
  }
  EXPECT_LT(std::fabs(glm::dot(world.transform(id).q, placement.q)), 0.99f);  // it did turn
}

TEST(CompoundBody, TheWorldMeetsTheConcaveShapeNotItsHull) {
  const Dumbbell& d = dumbbell();
  // The dumbbell's bottom at y = 2, turned about the vertical; a thin post of top y = 1.5 stands
  // under the middle of the bar, between the boxes.
  const Transform3 placement = Transform3::from_axis_angle({1.0f, 2.0f, -1.0f}, {0.0f, 1.0f, 0.0f}, 0.7f);
  const float post_top = 1.5f;
  const Vec3 under_bar = transform_point(placement, Vec3(2.5f, 0.0f, 0.5f));
  World3D world;
  const StaticId post = world.add_static(
      {.shapes = {make_box(Vec3(0.1f, 1.0f, 0.1f))}, .transform = Transform3{{under_bar.x, post_top - 1.0f, under_bar.z}, placement.q}});

  BodyDef3 def = make_compound_body(d.hulls, placement);
  def.velocity = Vec3(0.0f, -1.0f, 0.0f);
  def.user_id = 7;
  const BodyId body = world.add_body(def);
  const Vec3 c = compound_centroid(d.hulls);

  // Rays before it moves, mesh space mapped by the placement, along z: through the gap above
  // the bar (the hull of the whole mesh is there), through a box, through the bar.
  const auto ray = [&](Vec3 from) {
    return Ray3{transform_point(placement, from), rotate(placement.q, Vec3(0.0f, 0.0f, 5.0f))};
  };
  const QueryFilter bodies_only{.statics = false};
  const Ray3 gap = ray({2.5f, 0.85f, -2.0f});
  EXPECT_FALSE(world.raycast(gap, bodies_only).has_value());
  EXPECT_TRUE(raycast(make_convex_hull(d.vertices), placement, gap).hit);  // the hull would be hit
  struct Through {
    Vec3 from;
    float face_z;  ///< the mesh face the ray enters, z = this
  };
  for (const Through t : {Through{{0.5f, 0.85f, -2.0f}, 0.0f}, Through{{4.5f, 0.85f, -2.0f}, 0.0f},
                          Through{{2.5f, 0.5f, -2.0f}, 0.4f}}) {
    const auto hit = world.raycast(ray(t.from), bodies_only);
    ASSERT_TRUE(hit.has_value()) << t.from.x << ", " << t.from.y;
    EXPECT_FALSE(hit->collider.is_static);
    EXPECT_EQ(hit->collider.index, body.index);
    EXPECT_EQ(hit->user_id, 7u);
    EXPECT_NEAR(hit->hit.fraction, (t.face_z + 2.0f) / 5.0f, 0.1f / 5.0f);
  }

  // Falling at 1 m/s: the boxes pass either side of the post without a contact, the bar lands
  // on it. (The convex hull of the mesh would touch it 0.4 m higher, as the boxes' bottoms pass
  // its top.)
  int contact_steps = 0;
  float first_contact_bar = -1.0f;
  float lowest_untouched = 2.0f;  ///< the mesh's lowest bottom before the first contact
  for (int i = 0; i < 90; ++i) {
    world.step(1.0f / 60.0f);
    ASSERT_EQ(world.last_step_stats().tunnelled, 0) << "step " << i;
    // The mesh's bottom: the body's origin is the centroid c, turned only about y.
    const float bottom = world.transform(body).p.y - c.y;
    const float bar_bottom = bottom + 0.4f;
    bool touching = false;
    for (const Contact3& contact : world.contacts()) {
      EXPECT_EQ(contact.a.index, body.index);
      EXPECT_TRUE(contact.b.is_static && contact.b.index == post.index);
      touching = true;
    }
    if (touching) {
      ++contact_steps;
      if (first_contact_bar < 0.0f) first_contact_bar = bar_bottom;
      // Only the bar touches: its bottom is at the post's top (within the hulls' reach outside
      // the mesh, about a voxel and the concavity bound, and a step's motion).
      EXPECT_LT(bar_bottom, post_top + 0.12f) << "step " << i;
    } else if (first_contact_bar < 0.0f) {
      lowest_untouched = std::min(lowest_untouched, bottom);
    }
  }
  EXPECT_GT(contact_steps, 0);
  EXPECT_GT(first_contact_bar, post_top - 0.05f);  // and it did not sink into the post first
  EXPECT_LT(lowest_untouched, post_top - 0.25f);   // the boxes reached well past its top untouched
  EXPECT_GT(world.velocity(body).y, 0.0f);         // bounced off the post
}

TEST(CompoundBody, RejectsNoHullsBadHullsAndBadPlacements) {
  const auto message = [](auto&& make) -> std::string {
    try {
      make();
    } catch (const InvalidInput& e) {
      return e.what();
    }
    return "no throw";
  };
  const std::vector<ConvexHull> none;
  EXPECT_EQ(message([&] { (void)make_compound_body(none, Transform3{}); }), "compound hulls: none given");
  EXPECT_EQ(message([&] { (void)make_compound_static(none, Transform3{}); }), "compound hulls: none given");
  EXPECT_EQ(message([&] { (void)compound_centroid(none); }), "compound hulls: none given");

  const std::vector<ConvexHull> unbuilt{make_convex_hull(dumbbell().vertices), ConvexHull{}};
  EXPECT_NE(message([&] { (void)make_compound_body(unbuilt, Transform3{}); }).find("compound hulls[1]: no volume"), std::string::npos);
  EXPECT_NE(message([&] { (void)make_compound_static(unbuilt, Transform3{}); }).find("compound hulls[1]: no volume"), std::string::npos);

  const std::vector<ConvexHull> one{make_convex_hull(dumbbell().vertices)};
  const Transform3 not_unit{Vec3(0.0f), Quat{2.0f, 0.0f, 0.0f, 0.0f}};
  const Transform3 not_finite{Vec3(NAN, 0.0f, 0.0f), Quat{1.0f, 0.0f, 0.0f, 0.0f}};
  for (const Transform3& bad : {not_unit, not_finite}) {
    EXPECT_NE(message([&] { (void)make_compound_body(one, bad); }).find("compound placement:"), std::string::npos);
    EXPECT_NE(message([&] { (void)make_compound_static(one, bad); }).find("compound placement:"), std::string::npos);
  }
}

TEST(CompoundStatic, KeepsTheHullsPlacedAsGiven) {
  const std::vector<ConvexHull>& hulls = dumbbell().hulls;
  const Transform3 placement = Transform3::from_axis_angle({-4.0f, 1.0f, 2.0f}, {0.0f, 1.0f, 0.0f}, -0.4f);
  const StaticDef3 def = make_compound_static(hulls, placement);
  ASSERT_EQ(def.shapes.size(), hulls.size());
  EXPECT_VEC3_NEAR(def.transform.p, placement.p, 0.0f);
  for (std::size_t i = 0; i < hulls.size(); ++i) {
    ASSERT_TRUE(std::holds_alternative<ConvexHull>(def.shapes[i]));
    EXPECT_EQ(std::get<ConvexHull>(def.shapes[i]).vertices, hulls[i].vertices);
  }
  // In a world, a ray through the gap passes, one through a box stops.
  World3D world;
  world.add_static(def);
  const Vec3 along = rotate(placement.q, Vec3(0.0f, 0.0f, 5.0f));
  EXPECT_FALSE(world.raycast(Ray3{transform_point(placement, Vec3(2.5f, 0.85f, -2.0f)), along}).has_value());
  EXPECT_TRUE(world.raycast(Ray3{transform_point(placement, Vec3(0.5f, 0.85f, -2.0f)), along}).has_value());
}

}  // namespace
}  // namespace collide
