// Distance fields against independent truths: analytic distances of single shapes, the exact
// narrow phase, brute-force mesh distance and winding numbers (issue 17's proof).

#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>
#include <collide/ccd/raycast.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/sdf/distance_field.hpp>

#include "support/random.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace collide {
namespace {

/// Half a voxel diagonal: the bound for analytic fields.
template <int D>
float half_diagonal(float voxel) {
  return 0.5f * voxel * std::sqrt(float(D));
}

template <int D>
VecN<D> random_in(std::mt19937& rng, const AabbN<D>& box) {
  VecN<D> p;
  for (int k = 0; k < D; ++k) p[k] = test::uniform(rng, box.min[k], box.max[k]);
  return p;
}

/// Worst |field - exact| over random points in the grid.
template <class Field, class Exact>
float worst_error(const Field& field, Exact&& exact, int points, unsigned seed) {
  constexpr int D = Field::kDim;
  std::mt19937 rng(seed);
  float worst = 0.0f;
  for (int i = 0; i < points; ++i) {
    const VecN<D> p = random_in<D>(rng, field.grid.bounds());
    worst = std::max(worst, std::abs(field.sample(p) - exact(p)));
  }
  return worst;
}

FieldOptions options(float voxel) {
  FieldOptions o;
  o.voxel = voxel;
  return o;
}

TEST(DistanceField2D, CircleWithinHalfAVoxelDiagonal) {
  const Circle circle = make_circle({0.0f, 0.0f}, 2.0f);
  const std::vector<PlacedShape> shapes{{circle, Transform{{1.0f, -0.5f}, Rot2{}}}};
  const DistanceField field = make_distance_field(shapes, options(0.1f));
  const float error = worst_error(field, [](Vec2 p) { return glm::length(p - Vec2{1.0f, -0.5f}) - 2.0f; }, 4000, 1);
  EXPECT_LT(error, half_diagonal<2>(0.1f));
  EXPECT_TRUE(field.is_inside({1.0f, -0.5f}));
  EXPECT_FALSE(field.is_inside({3.5f, -0.5f}));
  EXPECT_GT(field.stats.band_nodes, 0u);
  EXPECT_EQ(field.stats.nodes, field.distances.size());
}

TEST(DistanceField2D, BoxAndCapsuleAgreeWithClosestPoint) {
  const std::vector<PlacedShape> shapes{
      {make_box({1.5f, 0.5f}), Transform::from({0.0f, 0.0f}, 0.3f)},
  };
  const DistanceField box_field = make_distance_field(shapes, options(0.05f));
  EXPECT_LT(worst_error(box_field, [&](Vec2 p) { return closest_point(shapes[0].shape, shapes[0].xf, p).distance; }, 4000, 2),
            half_diagonal<2>(0.05f));
  const std::vector<PlacedShape> capsule{{make_capsule({-1.0f, 0.0f}, {1.0f, 0.5f}, 0.4f), Transform{}}};
  const DistanceField capsule_field = make_distance_field(capsule, options(0.05f));
  EXPECT_LT(worst_error(capsule_field, [&](Vec2 p) { return closest_point(capsule[0].shape, capsule[0].xf, p).distance; }, 4000, 3),
            half_diagonal<2>(0.05f));
}

TEST(DistanceField2D, SeamBetweenAbuttingTilesIsNotASurface) {
  // Two unit tiles side by side make a 2 x 1 rectangle: its inside distance at the seam is 0.5
  // (to the top and bottom), not 0 (to the tiles' shared edge).
  const std::vector<PlacedShape> tiles{{make_box({0.5f, 0.5f}), Transform{{0.5f, 0.5f}, Rot2{}}},
                                       {make_box({0.5f, 0.5f}), Transform{{1.5f, 0.5f}, Rot2{}}}};
  const float voxel = 0.05f;
  const DistanceField field = make_distance_field(tiles, options(voxel));
  const std::vector<PlacedShape> whole{{make_box({1.0f, 0.5f}), Transform{{1.0f, 0.5f}, Rot2{}}}};
  const float error =
      worst_error(field, [&](Vec2 p) { return closest_point(whole[0].shape, whole[0].xf, p).distance; }, 4000, 4);
  EXPECT_LT(error, voxel);
  EXPECT_NEAR(field.sample({1.0f, 0.5f}), -0.5f, voxel);
}

TEST(DistanceField3D, SphereBoxCapsuleWithinHalfAVoxelDiagonal) {
  const float voxel = 0.1f;
  const std::vector<PlacedShape3> shapes[] = {
      {{make_sphere({0.0f, 0.0f, 0.0f}, 1.5f), Transform3{{0.2f, 0.1f, -0.3f}, Quat{1, 0, 0, 0}}}},
      {{make_box({1.0f, 0.5f, 0.75f}), Transform3::from_axis_angle({0, 0, 0}, glm::normalize(Vec3{1, 2, 3}), 0.7f)}},
      {{make_capsule(Vec3{-1.0f, 0.0f, 0.0f}, Vec3{1.0f, 0.5f, 0.0f}, 0.5f), Transform3{}}},
  };
  unsigned seed = 10;
  for (const auto& one : shapes) {
    const DistanceField3 field = make_distance_field(one, options(voxel));
    const float error =
        worst_error(field, [&](Vec3 p) { return closest_point(one[0].shape, one[0].xf, p).distance; }, 3000, ++seed);
    EXPECT_LT(error, half_diagonal<3>(voxel)) << type_name(one[0].shape);
  }
}

TEST(DistanceField3D, SampleFastPathGivesTheGeneralPathsValueBitForBit) {
  // sample takes an SSE2 path inside the grid's box; sample_cells' general path (locate, then
  // interpolate_cell) is the reference. They must agree exactly, value and gradient, on the
  // box's faces and last nodes too, and beyond the box (where both take the general path).
  const std::vector<PlacedShape3> scene{{make_sphere({0, 0, 0}, 1.0f), Transform3{{0.1f, 0.2f, -0.3f}, Quat{1, 0, 0, 0}}}};
  const DistanceField3 field = make_distance_field(scene, options(0.07f));
  const Aabb3 box = field.grid.bounds();
  std::mt19937 rng(31);
  for (int i = 0; i < 20000; ++i) {
    Vec3 p = random_in<3>(rng, box);
    if (i % 5 == 1) p[i % 3] = box.max[i % 3];  // on a far face: the last cell, fraction 1
    if (i % 5 == 2) p[i % 3] = box.min[i % 3];  // on a near face
    if (i % 5 == 3) p[i % 3] += (i % 2 ? 0.5f : -0.5f);  // beyond the box on one axis
    if (i % 5 == 4) p = field.grid.node(glm::ivec3(p[0] > 0, 1, 2) * (field.grid.dims - 1) / glm::ivec3(1, 2, 2));
    Vec3 general_gradient;
    const float general = sample_cells_located(field, p, &general_gradient);
    Vec3 g;
    ASSERT_EQ(field.sample(p), general) << p.x << " " << p.y << " " << p.z;
    ASSERT_EQ(field.sample(p, g), general) << p.x << " " << p.y << " " << p.z;
    ASSERT_EQ(g.x, general_gradient.x);
    ASSERT_EQ(g.y, general_gradient.y);
    ASSERT_EQ(g.z, general_gradient.z);
  }
}

TEST(DistanceField3D, SampleFastPathEdgeCoordinatesGiveTheGeneralPathsBits) {
  // The fast path tests "inside the box" on the floats' bits: -0 (a point at -0 over a grid at
  // origin 0), NaN of either sign, infinities, the last node and the next float past it must
  // give what the general path gives, bit for bit (NaN as NaN).
  const std::vector<PlacedShape3> scene{{make_sphere({0.5f, 0.5f, 0.5f}, 0.3f), Transform3{}}};
  DistanceField3 field = make_distance_field(scene, options(0.1f));
  field.grid.origin = Vec3(0.0f);  // the same values, now over a grid whose box starts at 0
  const Vec3 last = field.grid.node(field.grid.dims - 1);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const auto bits = [](float v) { return std::bit_cast<std::uint32_t>(v); };
  for (int axis = 0; axis < 3; ++axis) {
    const float specials[] = {-0.0f, 0.0f, nan, -nan, inf, -inf, last[axis], std::nextafter(last[axis], inf),
                              std::nextafter(0.0f, -inf), 0.3f};
    for (float s : specials) {
      Vec3 p(0.31f, 0.42f, 0.27f);
      p[axis] = s;
      Vec3 general_gradient;
      const float general = sample_cells_located(field, p, &general_gradient);
      Vec3 g;
      EXPECT_EQ(bits(field.sample(p)), bits(general)) << "axis " << axis << " coordinate " << s;
      EXPECT_EQ(bits(field.sample(p, g)), bits(general)) << "axis " << axis << " coordinate " << s;
      for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(g[k]), bits(general_gradient[k])) << "axis " << axis << " coordinate " << s;
    }
  }
}

/// Points for the batched sample: inside the grid's box, on its faces and last nodes, beyond it
/// on one axis or all, and a few NaN / infinite coordinates.
template <int D>
std::vector<VecN<D>> batch_points(const AabbN<D>& box, const FieldGridN<D>& grid, std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<VecN<D>> points(count);
  for (std::size_t i = 0; i < count; ++i) {
    VecN<D> p = random_in<D>(rng, box);
    const int k = static_cast<int>(i % D);
    if (i % 7 == 1) p[k] = box.max[k];
    if (i % 7 == 2) p[k] = box.min[k];
    if (i % 7 == 3) p[k] += (i % 2 ? 0.5f : -0.5f);
    if (i % 7 == 4) p = grid.node(grid.dims - 1);
    if (i % 97 == 5) p[k] = std::numeric_limits<float>::quiet_NaN();
    if (i % 101 == 6) p[k] = std::numeric_limits<float>::infinity();
    if (i % 11 == 0) p = box.max + VecN<D>(1.0f);
    points[i] = p;
  }
  return points;
}

/// sample(field, points, out) against field.sample one point at a time, bit for bit (NaN as
/// NaN), for every batch length around the lane width, and `out` shorter than the points.
template <class Field>
void expect_batch_is_one_at_a_time(const Field& field, unsigned seed) {
  constexpr int D = Field::kDim;
  const std::vector<VecN<D>> points = batch_points<D>(field.grid.bounds(), field.grid, 4099, seed);
  const auto same = [](float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); };
  std::vector<float> out(points.size() + 1, -7.0f);
  sample(field, std::span<const VecN<D>>(points), std::span<float>(out));
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_TRUE(same(out[i], field.sample(points[i]))) << "point " << i << ": " << out[i] << " vs " << field.sample(points[i]);
  }
  EXPECT_EQ(out.back(), -7.0f);  // past the points: untouched
  for (std::size_t n = 0; n <= 9; ++n) {  // short batches, from an offset that is not a multiple of 4
    std::vector<float> few(n, -7.0f);
    sample(field, std::span<const VecN<D>>(points.data() + 3, n), std::span<float>(few));
    for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(same(few[i], field.sample(points[3 + i]))) << n << " " << i;
  }
  std::vector<float> shorter(5, -7.0f);  // fewer outputs than points: only those sampled
  sample(field, std::span<const VecN<D>>(points), std::span<float>(shorter));
  for (std::size_t i = 0; i < shorter.size(); ++i) ASSERT_TRUE(same(shorter[i], field.sample(points[i])));
}

TEST(DistanceField, BatchedSampleIsOneAtATimeBitForBit) {
  // The dense 3D field's lane path (four points at a time) against the single sample; the other
  // fields take the loop, checked the same way.
  const std::vector<PlacedShape3> scene{{make_sphere({0, 0, 0}, 1.0f), Transform3{{0.1f, 0.2f, -0.3f}, Quat{1, 0, 0, 0}}},
                                        {make_box({0.5f, 0.3f, 0.4f}), Transform3{{0.9f, -0.6f, 0.2f}, Quat{1, 0, 0, 0}}}};
  expect_batch_is_one_at_a_time(make_distance_field(scene, options(0.07f)), 41);
  expect_batch_is_one_at_a_time(make_sparse_distance_field(scene, options(0.07f)), 42);
  const std::vector<PlacedShape> flat{{make_circle({0, 0}, 1.0f), Transform{{0.3f, -0.1f}, Rot2{}}}};
  expect_batch_is_one_at_a_time(make_distance_field(flat, options(0.05f)), 43);
  expect_batch_is_one_at_a_time(make_sparse_distance_field(flat, options(0.05f)), 44);
  // Far from the origin (large coordinates: the rounding of (p - origin) / voxel matters).
  const std::vector<PlacedShape3> far{{make_sphere({0, 0, 0}, 2.0f), Transform3{{3.0e4f, -1.5e4f, 7.0e3f}, Quat{1, 0, 0, 0}}}};
  expect_batch_is_one_at_a_time(make_distance_field(far, options(0.11f)), 45);
}

TEST(DistanceField, RefusesBadOptionsAndNamesTheMemoryItWouldNeed) {
  const std::vector<PlacedShape> shapes{{make_circle({0, 0}, 1.0f), Transform{}}};
  EXPECT_THROW((void)make_distance_field(shapes, options(0.0f)), InvalidInput);
  EXPECT_THROW((void)make_distance_field(shapes, options(std::nanf(""))), InvalidInput);
  EXPECT_THROW((void)make_distance_field(std::span<const PlacedShape>{}, options(0.1f)), InvalidInput);
  // No memory limit still leaves a limit on nodes (sizes must not overflow).
  FieldOptions unlimited = options(1e-9f);
  unlimited.max_bytes = std::numeric_limits<std::size_t>::max();
  EXPECT_THROW((void)make_distance_field(shapes, unlimited), InvalidInput);
  EXPECT_THROW((void)make_sparse_distance_field(shapes, unlimited), InvalidInput);
  FieldOptions tiny = options(1e-4f);
  tiny.max_bytes = std::size_t{1} << 20;
  try {
    (void)make_distance_field(shapes, tiny);
    FAIL() << "a grid over the limit was built";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("needs"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("MiB"), std::string::npos) << e.what();
  }
}


/// A closed UV sphere of radius r at c, outward wound (faces counter-clockwise from outside).
TriangleMesh sphere_mesh(Vec3 c, float r, int rings, int segments) {
  std::vector<Vec3> v;
  std::vector<glm::uvec3> t;
  v.push_back(c + Vec3{0, r, 0});
  for (int i = 1; i < rings; ++i) {
    const float theta = std::numbers::pi_v<float> * float(i) / float(rings);
    for (int j = 0; j < segments; ++j) {
      const float phi = 2.0f * std::numbers::pi_v<float> * float(j) / float(segments);
      v.push_back(c + r * Vec3{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
    }
  }
  v.push_back(c - Vec3{0, r, 0});
  const auto ring = [&](int i, int j) { return 1u + static_cast<unsigned>((i - 1) * segments + (j % segments)); };
  for (int j = 0; j < segments; ++j) t.push_back({0u, ring(1, j + 1), ring(1, j)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      t.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
      t.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
    }
  const auto last = static_cast<unsigned>(v.size() - 1);
  for (int j = 0; j < segments; ++j) t.push_back({last, ring(rings - 1, j), ring(rings - 1, j + 1)});
  return make_triangle_mesh(v, t);
}

TEST(WindingNumber, OneInsideAClosedMeshZeroOutside) {
  const TriangleMesh mesh = sphere_mesh({100.0f, 5.0f, -3.0f}, 2.0f, 16, 24);
  EXPECT_NEAR(winding_number(mesh, {100.0f, 5.0f, -3.0f}), 1.0f, 1e-3f);
  EXPECT_NEAR(winding_number(mesh, {101.5f, 5.0f, -3.0f}), 1.0f, 1e-3f);
  EXPECT_NEAR(winding_number(mesh, {103.0f, 5.0f, -3.0f}), 0.0f, 1e-3f);
  EXPECT_NEAR(winding_number(mesh, {0.0f, 0.0f, 0.0f}), 0.0f, 1e-3f);
}

TEST(DistanceField3D, MeshFieldAgreesWithBruteForceAndTheSignIsRight) {
  // A faceted sphere: exact distance to its triangles (brute force over all of them) and the
  // winding number's sign, against the fast build on every node.
  const TriangleMesh mesh = sphere_mesh({1.0f, 2.0f, 3.0f}, 1.5f, 10, 14);
  const float voxel = 0.1f;
  const DistanceField3 field = make_distance_field(mesh, options(voxel));
  ASSERT_EQ(field.distances.size(), field.grid.count());
  ASSERT_EQ(field.closest_points.size(), field.grid.count());
  float worst = 0.0f;
  int wrong_sign = 0;
  for (int z = 0; z < field.grid.dims.z; z += 2)
    for (int y = 0; y < field.grid.dims.y; y += 2)
      for (int x = 0; x < field.grid.dims.x; x += 2) {
        const Vec3 p = field.grid.node({x, y, z});
        float best = std::numeric_limits<float>::infinity();
        for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
          const Vec3 q = closest_point_on_triangle(p - mesh.origin, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)).point;
          best = std::min(best, glm::length(p - mesh.origin - q));
        }
        const float exact = winding_number(mesh, p) > 0.5f ? -best : best;
        const float value = field.distances[field.grid.index({x, y, z})];
        worst = std::max(worst, std::abs(value - exact));
        if (std::abs(exact) > 0.01f * voxel && (value < 0.0f) != (exact < 0.0f)) ++wrong_sign;
      }
  EXPECT_EQ(wrong_sign, 0);
  // Exact within the band; closest-point propagation beyond it stays within half a voxel.
  EXPECT_LT(worst, 0.5f * voxel);
  // The field's sign is the winding number's, exactly where the reference build says so too.
  const DistanceField3 exact = make_distance_field_exact(mesh, options(voxel));
  for (std::size_t i = 0; i < exact.distances.size(); i += 7)
    if (std::abs(exact.distances[i]) > voxel) ASSERT_EQ(exact.distances[i] < 0.0f, field.distances[i] < 0.0f) << i;
}

TEST(DistanceField3D, OpenLevelSignFollowsTheWindingNumber) {
  // dungeon.obj is open (no floor underside, holes): every node's sign against the brute-force
  // winding number, wherever that is clearly on one side of 1/2.
  const TriangleMesh mesh = io::load_triangle_mesh(std::string(COLLIDE_DATA_DIR) + "/meshes/recast/dungeon.obj");
  const float voxel = 1.0f;
  const DistanceField3 field = make_distance_field(mesh, options(voxel));
  std::mt19937 rng(7);
  int checked = 0, wrong = 0;
  for (int i = 0; i < 400; ++i) {
    glm::ivec3 n;
    for (int k = 0; k < 3; ++k) n[k] = std::uniform_int_distribution<int>(0, field.grid.dims[k] - 1)(rng);
    const float w = winding_number(mesh, field.grid.node(n));
    if (std::abs(w - 0.5f) < 0.1f) continue;
    ++checked;
    wrong += (field.distances[field.grid.index(n)] < 0.0f) != (w > 0.5f);
  }
  EXPECT_GT(checked, 300);
  EXPECT_EQ(wrong, 0);
  // Far above the level is outside, and the distance there is the height above its top.
  const Aabb3 top = field.grid.bounds();
  const Vec3 above{0.5f * (top.min.x + top.max.x), top.max.y, 0.5f * (top.min.z + top.max.z)};
  EXPECT_GT(field.sample(above), 0.0f);
}

TEST(SparseDistanceField, MatchesTheDenseFieldInTheBandAndClampsBeyond) {
  const TriangleMesh mesh = sphere_mesh({0.0f, 0.0f, 0.0f}, 2.0f, 12, 16);
  const float voxel = 0.1f;
  const DistanceField3 dense = make_distance_field(mesh, options(voxel));
  const SparseDistanceField3 sparse = make_sparse_distance_field(mesh, options(voxel));
  EXPECT_LT(sparse.bytes(), dense.bytes() / 4);
  EXPECT_FLOAT_EQ(sparse.band_distance, kFieldDefaultBand * voxel);
  std::mt19937 rng(8);
  for (int i = 0; i < 4000; ++i) {
    const Vec3 p = random_in<3>(rng, dense.grid.bounds());
    const float d = dense.sample(p);
    if (std::abs(d) < (kFieldDefaultBand - 1.5f) * voxel) {
      ASSERT_NEAR(sparse.sample(p), d, 1e-4f) << p.x << " " << p.y << " " << p.z;
    } else if (std::abs(d) > (kFieldDefaultBand + 1.5f) * voxel) {
      ASSERT_FLOAT_EQ(sparse.sample(p), d < 0.0f ? -sparse.band_distance : sparse.band_distance);
    }
    ASSERT_EQ(sparse.is_inside(p), dense.is_inside(p));
  }
  // 2D shapes too: a circle's sparse field against the analytic distance in the band.
  const std::vector<PlacedShape> circle{{make_circle({0, 0}, 3.0f), Transform{}}};
  const SparseDistanceField field2 = make_sparse_distance_field(circle, options(0.05f));
  for (int i = 0; i < 2000; ++i) {
    const Vec2 p = random_in<2>(rng, field2.grid.bounds());
    const float exact = glm::length(p) - 3.0f;
    if (std::abs(exact) < 1.5f * 0.05f) ASSERT_NEAR(field2.sample(p), exact, half_diagonal<2>(0.05f));
    if (std::abs(exact) > 0.5f) ASSERT_EQ(field2.sample(p) < 0.0f, exact < 0.0f);
  }
}

TEST(DistanceField3D, ClosestPointsStoredAndByGradient) {
  const Vec3 c{0.5f, -0.25f, 0.0f};
  const std::vector<PlacedShape3> sphere{{make_sphere({0, 0, 0}, 1.0f), Transform3{c, Quat{1, 0, 0, 0}}}};
  const float voxel = 0.05f;
  const DistanceField3 field = make_distance_field(sphere, options(voxel));
  std::mt19937 rng(9);
  float worst_stored = 0.0f, worst_gradient = 0.0f;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p = random_in<3>(rng, field.grid.bounds());
    // Near the centre the closest point turns fast with p (it has none at the centre): a voxel
    // of error in where the field was sampled becomes a large angle there.
    if (glm::length(p - c) < 0.6f) continue;
    const Vec3 exact = c + glm::normalize(p - c);
    worst_stored = std::max(worst_stored, glm::length(closest_point(field, p).closest - exact));
    worst_gradient = std::max(worst_gradient, glm::length(closest_point_by_gradient(field, p).closest - exact));
    ASSERT_EQ(closest_point(field, p).inside, glm::length(p - c) < 1.0f - voxel || (closest_point(field, p).inside && glm::length(p - c) < 1.0f + voxel));
  }
  // Stored closest points are those of the nodes around p (and propagated ones beyond the
  // band are a neighbour's): off by up to about a voxel per voxel of lever.
  EXPECT_LT(worst_stored, 2.0f * voxel);
  EXPECT_LT(worst_gradient, 2.0f * voxel);
}

TEST(DistanceField, ContactsAgreeWithTheExactNarrowPhase) {
  // A floor slab as the field; spheres, capsules and boxes pressed into it, against collide's
  // exact contact with the slab as a box.
  const float voxel = 0.05f;
  // Thick enough that no sample reaches its lower half (there the bottom face is nearer).
  const Box slab = make_box({4.0f, 2.0f, 4.0f});
  const Transform3 slab_xf{{0.0f, -2.0f, 0.0f}, Quat{1, 0, 0, 0}};
  const std::vector<PlacedShape3> floor{{slab, slab_xf}};
  const DistanceField3 field = make_distance_field(floor, options(voxel));
  const Shape3D shapes[] = {make_sphere({0, 0, 0}, 0.5f), make_capsule(Vec3{-0.5f, 0, 0}, Vec3{0.5f, 0, 0}, 0.3f),
                            make_box({0.4f, 0.3f, 0.5f})};
  std::mt19937 rng(11);
  for (const Shape3D& shape : shapes) {
    for (int i = 0; i < 50; ++i) {
      const Transform3 xf{{test::uniform(rng, -1, 1), test::uniform(rng, 0.1f, 0.45f), test::uniform(rng, -1, 1)},
                          test::random_rotation(rng)};
      const Manifold3 exact = contact(shape, xf, Shape3D{slab}, slab_xf);
      const Manifold3 sampled = contact(shape, xf, field);
      ASSERT_EQ(exact.touching(), sampled.touching()) << type_name(shape) << " " << exact.max_depth();
      if (!exact.touching()) continue;
      EXPECT_NEAR(sampled.max_depth(), exact.max_depth(), voxel) << type_name(shape);
      EXPECT_GT(glm::dot(sampled.normal, exact.normal), 0.99f) << type_name(shape);
    }
  }
  // A point: depth and normal from the field.
  const Manifold3 point = contact(Vec3{0.3f, -0.2f, 0.1f}, field);
  ASSERT_EQ(point.count, 1);
  EXPECT_NEAR(point.points[0].depth, 0.2f, 0.5f * voxel);
  EXPECT_NEAR(point.normal.y, -1.0f, 0.01f);                 // from the point down into the floor
  EXPECT_EQ(contact(Vec3{0.3f, 0.2f, 0.1f}, field).count, 0);
  // 2D: a circle on a box.
  const std::vector<PlacedShape> ground{{make_box({5.0f, 1.0f}), Transform{{0.0f, -1.0f}, Rot2{}}}};
  const DistanceField field2 = make_distance_field(ground, options(voxel));
  const Manifold m = contact(Shape2D{make_circle({0, 0}, 0.5f)}, Transform{{1.0f, 0.3f}, Rot2{}}, field2);
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].depth, 0.2f, 0.5f * voxel);
  EXPECT_NEAR(m.normal.y, -1.0f, 0.01f);
}

TEST(DistanceField, RaymarchHitsWhereTheExactRayCastDoes) {
  const float voxel = 0.05f;
  const Sphere ball = make_sphere({0, 0, 0}, 1.0f);
  const Transform3 xf{{0.2f, 0.1f, -0.3f}, Quat{1, 0, 0, 0}};
  const std::vector<PlacedShape3> scene{{ball, xf}};
  const DistanceField3 field = make_distance_field(scene, options(voxel));
  const SparseDistanceField3 sparse = make_sparse_distance_field(scene, options(voxel));
  std::mt19937 rng(12);
  int hits = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 from = 1.3f * test::random_unit3(rng) * 1.2f;
    const Vec3 to = 0.6f * test::random_point3(rng, 1.0f);
    const Ray3 ray{from, 2.0f * (to - from)};
    const RayHit3 exact = raycast(ball, xf, ray);
    for (const RayHit3 marched : {raymarch(field, ray), raymarch(sparse, ray)}) {
      if (glm::length(from - xf.p) <= 1.0f + voxel) continue;  // starts inside or on it
      ASSERT_EQ(marched.hit, exact.hit);
      if (!exact.hit) continue;
      ++hits;
      // On the surface to within the field's error; where the exact one is, unless the ray
      // grazes the ball (then a small error in distance moves the hit far along the ray).
      EXPECT_LT(std::abs(glm::length(marched.point - xf.p) - 1.0f), 0.5f * voxel);
      if (-glm::dot(exact.normal, glm::normalize(ray.translation)) > 0.3f) {
        EXPECT_LT(glm::length(marched.point - exact.point), voxel);
        EXPECT_GT(glm::dot(marched.normal, exact.normal), 0.98f);
      }
    }
  }
  EXPECT_GT(hits, 100);
  // Soft shadows: blocked behind the ball, lit beside it, half-lit in between.
  EXPECT_EQ(soft_shadow(field, Ray3{xf.p + Vec3{0, 0, -3}, Vec3{0, 0, 6}}, 16.0f), 0.0f);
  EXPECT_EQ(soft_shadow(field, Ray3{xf.p + Vec3{0, 2.5f, -3}, Vec3{0, 0, 6}}, 16.0f), 1.0f);
  const float penumbra = soft_shadow(field, Ray3{xf.p + Vec3{0, 1.05f, -3}, Vec3{0, 0, 6}}, 16.0f);
  EXPECT_GT(penumbra, 0.0f);
  EXPECT_LT(penumbra, 1.0f);
}

TEST(DistanceField, ParticlesBounceAndNeverEndInside) {
  const float voxel = 0.1f;
  const std::vector<PlacedShape3> floor{{make_box({3.0f, 0.5f, 3.0f}), Transform3{{0, -0.5f, 0}, Quat{1, 0, 0, 0}}}};
  const DistanceField3 field = make_distance_field(floor, options(voxel));
  Particles3 particles;
  std::mt19937 rng(13);
  for (int i = 0; i < 1000; ++i) {
    particles.positions.push_back({test::uniform(rng, -2, 2), test::uniform(rng, 0.2f, 0.8f), test::uniform(rng, -2, 2)});
    particles.velocities.push_back({0.0f, -test::uniform(rng, 1.0f, 5.0f), 0.0f});
  }
  std::size_t bounced = 0;
  for (int frame = 0; frame < 30; ++frame) {
    bounced += step_particles(field, particles, 1.0f / 60.0f, 0.5f).bounced;
    for (const Vec3& p : particles.positions) ASSERT_GE(field.sample(p), -1e-3f);
  }
  EXPECT_GT(bounced, 500u);
  for (const Vec3& v : particles.velocities) EXPECT_GE(v.y, -5.0f);  // the floor turned them back
  int rising = 0;
  for (const Vec3& v : particles.velocities) rising += v.y > 0.0f;
  EXPECT_GT(rising, 500);
}

/// step_particles' documented rule, one particle at a time, for the test below: move; done when
/// the nearest node is in the grid and farther out than a voxel diagonal; else sample, and push
/// out and reflect when inside.
template <class F>
ParticleStepStats reference_step(const F& field, ParticlesN<F::kDim>& particles, float dt, float restitution) {
  constexpr int D = F::kDim;
  ParticleStepStats stats;
  const float clear = field.grid.voxel * std::sqrt(float(D));
  for (std::size_t i = 0; i < particles.positions.size(); ++i) {
    VecN<D>& position = particles.positions[i];
    VecN<D>& velocity = particles.velocities[i];
    position = position + velocity * dt;
    glm::vec<D, int> node;
    if (field.grid.nearest_node(position, node) && field.node_value(node) > clear) continue;
    ++stats.near;
    VecN<D> g;
    const float d = field.sample(position, g);
    const float gl = glm::length(g);
    if (!(d < 0.0f) || !(gl > 0.0f)) continue;
    const VecN<D> normal = g / gl;
    position = position - d * normal;
    const float vn = glm::dot(velocity, normal);
    if (vn < 0.0f) velocity -= (1.0f + restitution) * vn * normal;
    ++stats.bounced;
  }
  return stats;
}

/// Bitwise equality of two float vectors (NaN equal to the same NaN).
template <int D>
bool same_bits(VecN<D> a, VecN<D> b) {
  for (int k = 0; k < D; ++k)
    if (std::bit_cast<std::uint32_t>(a[k]) != std::bit_cast<std::uint32_t>(b[k])) return false;
  return true;
}

/// Particles for the test below: most in the grid's box (some near the surface), some beyond
/// it by more than half a voxel, a few with NaN or infinite coordinates or velocities.
template <int D>
ParticlesN<D> mixed_particles(const AabbN<D>& box, int count, unsigned seed) {
  std::mt19937 rng(seed);
  ParticlesN<D> out;
  const VecN<D> size = box.max - box.min;
  for (int i = 0; i < count; ++i) {
    const AabbN<D> wide{box.min - 0.1f * size, box.max + 0.1f * size};
    VecN<D> p = random_in<D>(rng, i % 5 == 0 ? wide : box);
    VecN<D> v = random_in<D>(rng, AabbN<D>{-size, size});
    if (i % 97 == 3) p[i % D] = std::numeric_limits<float>::quiet_NaN();
    if (i % 89 == 5) v[(i + 1) % D] = std::numeric_limits<float>::infinity();
    out.positions.push_back(p);
    out.velocities.push_back(v);
  }
  return out;
}

/// step_particles works in chunks, four particles at a time in SSE lanes on dense fields; every
/// particle must end where the one-at-a-time rule puts it, bit for bit, and the counts agree.
/// Counts around the chunk size and not multiples of four take the tails.
template <class F>
void expect_step_matches_reference(const F& field, unsigned seed) {
  constexpr int D = F::kDim;
  for (const int count : {0, 1, 3, 4, 255, 256, 257, 1027}) {
    ParticlesN<D> fast = mixed_particles<D>(field.grid.bounds(), count, seed + static_cast<unsigned>(count));
    ParticlesN<D> slow = fast;
    std::size_t bounced = 0;
    for (int frame = 0; frame < 20; ++frame) {
      const ParticleStepStats a = step_particles(field, fast, 0.05f, 0.5f);
      const ParticleStepStats b = reference_step(field, slow, 0.05f, 0.5f);
      ASSERT_EQ(a.near, b.near) << "count " << count << " frame " << frame;
      ASSERT_EQ(a.bounced, b.bounced) << "count " << count << " frame " << frame;
      bounced += a.bounced;
      for (int i = 0; i < count; ++i) {
        ASSERT_TRUE(same_bits<D>(fast.positions[i], slow.positions[i])) << "particle " << i << " of " << count;
        ASSERT_TRUE(same_bits<D>(fast.velocities[i], slow.velocities[i])) << "particle " << i << " of " << count;
      }
    }
    if (count >= 256) EXPECT_GT(bounced, 0u) << "count " << count;  // the test reaches the solid
  }
}

TEST(DistanceField, ParticleStepIsTheOneAtATimeRuleBitForBit) {
  const float voxel = 0.1f;
  const std::vector<PlacedShape3> scene{{make_box({1.0f, 0.6f, 0.8f}), Transform3{{0.1f, -0.2f, 0.05f}, Quat{1, 0, 0, 0}}},
                                        {make_sphere({0, 0, 0}, 0.7f), Transform3{{1.2f, 0.9f, -0.4f}, Quat{1, 0, 0, 0}}}};
  expect_step_matches_reference(make_distance_field(scene, options(voxel)), 31);
  expect_step_matches_reference(make_sparse_distance_field(scene, options(voxel)), 32);
  const std::vector<PlacedShape> flat{{make_circle({0, 0}, 1.0f), Transform{{0.3f, -0.1f}, Rot2{}}},
                                      {make_box({0.8f, 0.4f}), Transform{{-1.2f, 0.6f}, Rot2{}}}};
  expect_step_matches_reference(make_distance_field(flat, options(0.05f)), 33);
  expect_step_matches_reference(make_sparse_distance_field(flat, options(0.05f)), 34);
}

}  // namespace
}  // namespace collide
