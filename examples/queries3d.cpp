// The same questions in 3D, one call each, the names the same as in 2D:
//   does it touch?            overlap
//   where and how deep?       contact (manifold: normal from A to B, up to 4 points, feature ids)
//   how deep, exactly?        penetration (EPA)
//   how far?                  distance (GJK; closest points)
//   what does a ray hit?      raycast (convex shapes, triangle meshes, height fields)
//   when will it hit?         shape_cast (translation), time_of_impact (with rotation)
// Transform3 places a shape: a position and a unit quaternion (w, x, y, z). y is up.

#include <collide/ccd/raycast.hpp>
#include <collide/ccd/shape_cast.hpp>
#include <collide/ccd/time_of_impact.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/epa.hpp>
#include <collide/narrow/overlap.hpp>
#include <collide/shape/convex_hull.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <cstdio>
#include <vector>

int main() {
  using namespace collide;
  const Box floor = make_box({10.0f, 0.5f, 10.0f});         // half extents: 20 x 1 x 20
  const Box crate = make_box({0.5f, 0.5f, 0.5f}, 0.02f);    // a slightly rounded 1 m crate
  const Sphere ball = make_sphere({0.0f, 0.0f, 0.0f}, 0.25f);
  const Capsule3 player = make_capsule({0.0f, -0.6f, 0.0f}, {0.0f, 0.6f, 0.0f}, 0.3f);
  const std::vector<Vec3> rock_points = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.1f, 0.0f},
                                         {0.2f, 0.9f, 0.1f}, {0.1f, 0.2f, 1.1f},
                                         {0.8f, 0.7f, 0.9f}, {0.5f, 0.5f, 0.5f}};
  const ConvexHull rock = make_convex_hull(rock_points);  // quickhull; inner points dropped

  const Transform3 floor_at{};  // identity
  // The crate sinks 1 cm into the floor, turned 0.3 rad about y.
  const Transform3 crate_at =
      Transform3::from({2.0f, 0.99f, 0.0f}, glm::angleAxis(0.3f, Vec3{0.0f, 1.0f, 0.0f}));
  const Transform3 player_at = Transform3::from({-3.0f, 1.5f, 0.0f}, Quat{1.0f, 0.0f, 0.0f, 0.0f});

  std::printf("crate overlaps floor: %s\n", overlap(floor, floor_at, crate, crate_at) ? "yes" : "no");

  const Manifold3 m = contact(floor, floor_at, crate, crate_at);
  std::printf("contact: %d points, normal (%.2f, %.2f, %.2f)\n", m.count, m.normal.x, m.normal.y,
              m.normal.z);
  for (int i = 0; i < m.count; ++i) {
    const ManifoldPoint3& p = m.points[i];
    std::printf("  point (%.3f, %.3f, %.3f) depth %.4f id %016llx\n", p.point.x, p.point.y,
                p.point.z, p.depth, static_cast<unsigned long long>(p.id.key()));
  }
  const PenetrationResult3 pen = penetration(floor, floor_at, crate, crate_at);
  std::printf("EPA depth %.4f along (%.2f, %.2f, %.2f)\n", pen.depth, pen.normal.x, pen.normal.y,
              pen.normal.z);

  const DistanceResult3 d = distance(player, player_at, floor, floor_at);
  std::printf("player stands %.3f above the floor\n", d.distance);

  // A ball thrown at the rock: when does it touch (translation only), and with spin?
  const Transform3 rock_at = Transform3::from({6.0f, 0.5f, 0.0f}, Quat{1.0f, 0.0f, 0.0f, 0.0f});
  const Transform3 ball_at = Transform3::from({0.0f, 1.0f, 0.5f}, Quat{1.0f, 0.0f, 0.0f, 0.0f});
  const Vec3 throw_by{10.0f, 0.0f, 0.0f};  // this step's translation
  const ShapeCastResult3 cast = shape_cast(ball, ball_at, throw_by, rock, rock_at, Vec3{0.0f});
  if (cast.hit) std::printf("ball touches the rock at %.3f of the step\n", cast.fraction);
  const Sweep3 spin = Sweep3::from_motion(ball_at, Vec3{0.0f}, throw_by, Vec3{0.0f, 0.0f, 20.0f});
  const Sweep3 still = Sweep3::from_motion(rock_at, Vec3{0.0f}, Vec3{0.0f}, Vec3{0.0f});
  const ToiResult3 toi = time_of_impact(ball, spin, rock, still);
  std::printf("with spin: time of impact %.3f (%s)\n", toi.fraction, to_string(toi.status));
  // Line of sight from the ball to a point behind the rock: the fraction alone is enough.
  const Vec3 eye = ball_at.p, behind{9.0f, 1.0f, 0.5f};
  const RayFraction sight = raycast_fraction(rock, rock_at, Ray3{eye, behind - eye});
  std::printf("the rock %s the view (at %.3f of the way)\n", sight.hit ? "blocks" : "leaves", sight.fraction);

  // A mouse pick against a level mesh: two triangles making a ramp.
  const std::vector<Vec3> level_vertices = {
      {0.0f, 0.0f, -2.0f}, {4.0f, 1.0f, -2.0f}, {4.0f, 1.0f, 2.0f}, {0.0f, 0.0f, 2.0f}};
  const std::vector<glm::uvec3> level_triangles = {{0, 2, 1}, {0, 3, 2}};
  const TriangleMesh ramp = make_triangle_mesh(level_vertices, level_triangles);
  const RayHit3 pick = raycast(ramp, Transform3{}, Ray3{{2.0f, 5.0f, 0.5f}, {0.0f, -10.0f, 0.0f}});
  if (pick.hit) {
    std::printf("pick hits triangle %u at (%.2f, %.2f, %.2f)\n", pick.sub_shape, pick.point.x,
                pick.point.y, pick.point.z);
  }
  return 0;
}
