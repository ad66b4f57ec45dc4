#pragma once
/// @file
/// Contact manifolds: where and how deep two shapes touch, with feature ids stable across frames.

#include <collide/core/aabb.hpp>

#include <array>
#include <cstdint>

namespace collide {

/// Kind of feature a contact point or a closest point comes from.
enum class FeatureType : std::uint8_t {
  vertex,  ///< a vertex (circle centre, capsule end, polygon or hull corner)
  edge,    ///< an edge (2D polygon: edge i runs from vertex i to vertex i + 1)
  face,    ///< a 2D solid's one curved face (a circle), or a 3D face
};

/// Feature indices are below this bound, so a ContactId packs into 64 bits. A mesh names its
/// edges 3 * triangle + k, which allows meshes of up to 2^30 / 3 (about 358 million) triangles.
inline constexpr std::uint32_t kMaxFeatureIndex = 1u << 30;

/// A feature of a shape: its kind and index. Indices per shape (DESIGN.md, "Feature ids"):
/// 2D polygon vertex i / edge i; circle face 0; capsule and segment vertex 0 (a), vertex 1 (b),
/// edge 0 (the side to the right of a -> b), edge 1. 3D hull vertex, edge (`ConvexHull::edges`
/// index) or face; box vertex / edge / face (box.hpp); sphere face 0; a mesh or height field
/// names features globally: vertex = mesh vertex, edge = 3 * triangle + k, face = triangle.
struct Feature {
  FeatureType type = FeatureType::vertex;
  std::uint32_t index = 0;  ///< < kMaxFeatureIndex
  friend constexpr bool operator==(Feature, Feature) noexcept = default;
};

/// Which features of A and B produced a contact point: e.g. a clipped point made by vertex 2 of
/// B's incident edge against reference edge 0 of A, or a box's face against triangle 1234 of a
/// level mesh. Games match contacts across frames by `key()` (Box2D b2ContactFeature; Jolt
/// SubShapeID; Catto, "Contact Manifolds", GDC 2007).
struct ContactId {
  std::uint32_t index_a = 0;                 ///< feature index on A, < kMaxFeatureIndex
  std::uint32_t index_b = 0;                 ///< feature index on B, < kMaxFeatureIndex
  FeatureType type_a = FeatureType::vertex;  ///< kind of feature on A
  FeatureType type_b = FeatureType::vertex;  ///< kind of feature on B

  /// The fields packed into one integer, for hashing and comparison: A's feature in the low
  /// 32 bits (index, type in bits 30-31), B's in the high 32.
  [[nodiscard]] constexpr std::uint64_t key() const noexcept {
    const std::uint64_t a = index_a | (std::uint64_t(type_a) << 30);
    const std::uint64_t b = index_b | (std::uint64_t(type_b) << 30);
    return a | (b << 32);
  }
  /// A's feature.
  [[nodiscard]] constexpr Feature feature_a() const noexcept { return {type_a, index_a}; }
  /// B's feature.
  [[nodiscard]] constexpr Feature feature_b() const noexcept { return {type_b, index_b}; }
  friend constexpr bool operator==(ContactId, ContactId) noexcept = default;
};

/// Most points a manifold holds: 2 in 2D (the ends of a touching stretch), 4 in 3D (a touching
/// patch reduced to its four most spread points).
template <int D>
inline constexpr int kMaxManifoldPoints = D == 2 ? 2 : 4;

/// One contact point, in D dimensions.
template <int D>
struct ManifoldPointN {
  /// World space, midway between the two surfaces. A's deepest surface point is
  /// `point + 0.5 * depth * normal`, B's is `point - 0.5 * depth * normal`.
  VecN<D> point{0.0f};
  /// Penetration depth along the manifold normal, world units: >= 0 when touching (0: just
  /// touching); negative for a speculative point of shapes apart by less than the caller's
  /// margin (3D contact with a margin only).
  float depth = 0.0f;
  /// Features of A and B that made this point.
  ContactId id{};
};

/// The contact between two shapes: 0 points when they do not touch, else up to
/// kMaxManifoldPoints<D> points that share one normal.
template <int D>
struct ManifoldN {
  VecN<D> normal{0.0f};  ///< unit, from A to B, world space; zero when count == 0
  std::array<ManifoldPointN<D>, kMaxManifoldPoints<D>> points{};
  int count = 0;  ///< number of valid points, 0..kMaxManifoldPoints<D>

  /// True when the shapes touch or overlap (count > 0).
  [[nodiscard]] bool touching() const noexcept { return count > 0; }
  /// Largest depth over the points; 0 when not touching.
  [[nodiscard]] float max_depth() const noexcept {
    float d = 0.0f;
    for (int i = 0; i < count; ++i) d = points[i].depth > d ? points[i].depth : d;
    return d;
  }
};

using ManifoldPoint = ManifoldPointN<2>;   ///< 2D contact point
using ManifoldPoint3 = ManifoldPointN<3>;  ///< 3D contact point
using Manifold = ManifoldN<2>;             ///< 2D manifold: up to 2 points
using Manifold3 = ManifoldN<3>;            ///< 3D manifold: up to 4 points

/// The same features named from the other side: A's and B's fields swapped.
[[nodiscard]] constexpr ContactId swapped(ContactId id) noexcept {
  return ContactId{id.index_b, id.index_a, id.type_b, id.type_a};
}

/// Turns `m` into the same manifold seen from the other side, in place: normal flipped, A and
/// B swapped in every id. With `reversed`, the one place the library swaps A and B (STYLE.md:
/// never flip by hand at call sites). In place so that a manifold built in the caller's return
/// slot is flipped there, not copied.
template <int D>
constexpr void reverse(ManifoldN<D>& m) noexcept {
  m.normal = -m.normal;
  for (int i = 0; i < m.count; ++i) m.points[i].id = swapped(m.points[i].id);
}

/// The same manifold seen from the other side: normal flipped, A and B swapped in every id.
template <int D>
[[nodiscard]] constexpr ManifoldN<D> reversed(ManifoldN<D> m) noexcept {
  reverse(m);
  return m;
}

}  // namespace collide
