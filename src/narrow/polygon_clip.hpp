#pragma once
// Internal: the two geometric steps of polygon contact after the separating axis test, on edges
// given in one frame (A's local frame in `contact`).
//  - clip_incident_edge: clip the incident edge to the slab between the reference edge's side
//    planes (Sutherland-Hodgman on a segment; Catto, "Contact Manifolds", GDC 2007;
//    Ericson, Real-Time Collision Detection, 8.3.2).

#include <array>
#include <collide/narrow/manifold.hpp>

namespace collide::detail {

/// A point of the clipped incident edge, with the features that made it (reference polygon as
/// "A", incident polygon as "B").
struct ClipVertex {
  Vec2 point{0.0f, 0.0f};
  ContactId id{};
};

/// The incident edge after clipping: 0 points (it lies beside the reference edge) or 2.
struct ClippedEdge {
  std::array<ClipVertex, 2> vertices{};
  int count = 0;
};

/// A polygon edge named by its end points and indices.
struct EdgeRef {
  Vec2 start{0.0f, 0.0f};  ///< vertex `index`
  Vec2 end{0.0f, 0.0f};    ///< vertex `next`
  int index = 0;           ///< edge index = index of its start vertex
  int next = 0;            ///< index of its end vertex (index + 1 mod count)
};

/// Clips `incident` to the slab lower <= dot(tangent, p) <= upper, where lower and upper are
/// the tangent coordinates of the reference edge's ends and `tangent` its unit direction.
/// Kept incident vertices get id (reference edge, incident vertex); points cut by a side plane
/// get id (reference vertex of that plane, incident edge).
[[nodiscard]] ClippedEdge clip_incident_edge(const EdgeRef& reference, Vec2 tangent,
                                             const EdgeRef& incident) noexcept;

}  // namespace collide::detail
