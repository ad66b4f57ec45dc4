#pragma once
/// @file
/// Contact manifolds: where and how deep two shapes touch, with feature ids stable across frames.

#include <collide/core/math.hpp>

#include <array>
#include <cstdint>

namespace collide {

/// Kind of feature a contact point or a closest point comes from.
enum class FeatureType : std::uint8_t {
  vertex,  ///< a vertex (circle centre, capsule end, polygon corner)
  edge,    ///< an edge (edge i runs from vertex i to vertex i + 1)
  face,    ///< a 2D solid's one curved face (a circle) or a 3D face
};

/// Which features of A and B produced a contact point: e.g. a clipped point made by vertex 2 of
/// B's incident edge against reference edge 0 of A. Games match contacts across frames by
/// `key()` (Box2D b2ContactFeature; Catto, "Contact Manifolds", GDC 2007).
struct ContactId {
  std::uint8_t index_a = 0;                 ///< vertex or edge index on A
  std::uint8_t index_b = 0;                 ///< vertex or edge index on B
  FeatureType type_a = FeatureType::vertex;  ///< kind of feature on A
  FeatureType type_b = FeatureType::vertex;  ///< kind of feature on B

  /// The four fields packed into one integer, for hashing and comparison.
  [[nodiscard]] constexpr std::uint32_t key() const noexcept {
    return std::uint32_t{index_a} | (std::uint32_t{index_b} << 8) |
           (std::uint32_t(type_a) << 16) | (std::uint32_t(type_b) << 24);
  }
  friend constexpr bool operator==(ContactId, ContactId) noexcept = default;
};

/// One contact point.
struct ManifoldPoint {
  /// World space, midway between the two surfaces. A's deepest surface point is
  /// `point + 0.5 * depth * normal`, B's is `point - 0.5 * depth * normal`.
  Vec2 point{0.0f, 0.0f};
  /// Penetration depth along the manifold normal, world units, >= 0 (0: touching).
  float depth = 0.0f;
  /// Features of A and B that made this point.
  ContactId id{};
};

/// The contact between two shapes: 0 points when they do not touch, else 1 or 2 points that
/// share one normal.
struct Manifold {
  Vec2 normal{0.0f, 0.0f};  ///< unit, from A to B, world space; zero when count == 0
  std::array<ManifoldPoint, 2> points{};
  int count = 0;  ///< number of valid points, 0..2

  /// True when the shapes touch or overlap (count > 0).
  [[nodiscard]] bool touching() const noexcept { return count > 0; }
  /// Largest depth over the points; 0 when not touching.
  [[nodiscard]] float max_depth() const noexcept {
    float d = 0.0f;
    for (int i = 0; i < count; ++i) d = points[i].depth > d ? points[i].depth : d;
    return d;
  }
};

/// The same features named from the other side: A's and B's fields swapped.
[[nodiscard]] constexpr ContactId swapped(ContactId id) noexcept {
  return ContactId{id.index_b, id.index_a, id.type_b, id.type_a};
}

/// Turns `m` into the same manifold seen from the other side, in place: normal flipped, A and
/// B swapped in every id. With `reversed`, the one place the library swaps A and B (STYLE.md:
/// never flip by hand at call sites). In place so that a manifold built in the caller's return
/// slot is flipped there, not copied.
constexpr void reverse(Manifold& m) noexcept {
  m.normal = -m.normal;
  for (int i = 0; i < m.count; ++i) m.points[i].id = swapped(m.points[i].id);
}

/// The same manifold seen from the other side: normal flipped, A and B swapped in every id.
[[nodiscard]] constexpr Manifold reversed(Manifold m) noexcept {
  reverse(m);
  return m;
}

}  // namespace collide
