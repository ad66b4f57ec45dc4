// A concave prop as a World3D body: a table (a top on four legs) made as triangles, split into
// convex hulls by decompose_approximate once at load time, and dropped onto a floor as one
// compound body over a crate. Its legs land around the crate, never touching it: under the top
// there is room (a ray between the legs passes too), which the convex hull of the table would fill.

#include <collide/decompose/approximate_decomposition.hpp>
#include <collide/world/compound.hpp>
#include <collide/world/world3d.hpp>

#include <cstdio>
#include <vector>

namespace {

using namespace collide;

/// Appends the 12 triangles of the box [lo, hi], outward wound.
void add_box(std::vector<Vec3>& vertices, std::vector<glm::uvec3>& triangles, Vec3 lo, Vec3 hi) {
  const auto base = static_cast<unsigned>(vertices.size());
  for (int c = 0; c < 8; ++c) vertices.push_back({c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z});
  const unsigned faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces) {
    triangles.push_back({base + f[0], base + f[1], base + f[2]});
    triangles.push_back({base + f[0], base + f[2], base + f[3]});
  }
}

}  // namespace

int main() {
  // The table, mesh space (metres, y up): a 2 x 0.1 x 1.2 top at height 0.8 on four 0.1 m legs.
  std::vector<Vec3> vertices;
  std::vector<glm::uvec3> triangles;
  add_box(vertices, triangles, {-1.0f, 0.8f, -0.6f}, {1.0f, 0.9f, 0.6f});
  for (const float x : {-0.9f, 0.8f}) {
    for (const float z : {-0.5f, 0.4f}) add_box(vertices, triangles, {x, 0.0f, z}, {x + 0.1f, 0.8f, z + 0.1f});
  }
  const TriangleMesh mesh = make_triangle_mesh(vertices, triangles);
  const ApproximateDecomposition parts = decompose_approximate(mesh);  // at load time, not per frame
  std::printf("table: %zu triangles -> %zu convex hulls (%.2f s)\n", mesh.triangles.size(), parts.hulls.size(),
              parts.seconds);

  World3D world(WorldOptions3{.gravity = {0.0f, -9.81f, 0.0f}});
  world.add_static({.shapes = {make_box({10.0f, 0.5f, 10.0f})}, .transform = Transform3{{0.0f, -0.5f, 0.0f}}, .user_id = 1});
  // A crate on the floor, right under the table and lower than its top: it fits between the legs.
  world.add_static({.shapes = {make_box({0.3f, 0.3f, 0.3f})}, .transform = Transform3{{0.0f, 0.3f, 0.0f}}, .user_id = 3});
  // The mesh placed 1 m up, turned 0.5 rad about y (the body turns about the hulls' centroid).
  BodyDef3 table = make_compound_body(parts.hulls, Transform3::from_axis_angle({0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0.5f));
  table.user_id = 2;
  const BodyId id = world.add_body(table);
  std::printf("a ray under the top, between the legs: %s\n",
              world.raycast(Ray3{{0.0f, 1.5f, -2.0f}, {0.0f, 0.0f, 4.0f}}) ? "hits the table" : "passes");

  int crate_touches = 0;
  for (int frame = 1; frame <= 60; ++frame) {
    world.step(1.0f / 60.0f);
    for (const ContactEvent3& e : world.events()) {
      if (e.type != ContactEventType::begin) continue;
      std::printf("frame %2d: hull %u of the table touches the %s\n", frame, static_cast<unsigned>(e.a.piece),
                  e.user_b == 3 ? "crate" : "floor");
      crate_touches += e.user_b == 3 ? 1 : 0;
    }
  }
  // The world's response is kinematic: the table bounces rather than settles.
  std::printf("after 1 s: table at height %.2f, %lld contacts in all, %d with the crate, tunnelled %lld\n",
              static_cast<double>(world.transform(id).p.y), static_cast<long long>(world.total_stats().contacts),
              crate_touches, static_cast<long long>(world.total_stats().tunnelled));
  return world.total_stats().tunnelled == 0 && crate_touches == 0 ? 0 : 1;
}
