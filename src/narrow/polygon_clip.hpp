#pragma once
// Internal: the two geometric steps of polygon contact after the separating axis test, on edges
// given in one frame (A's local frame in `contact`).
//  - clip_incident_edge: clip the incident edge to the slab between the reference edge's side
//    planes (Sutherland-Hodgman on a segment; Catto, "Contact Manifolds", GDC 2007;
//    Ericson, Real-Time Collision Detection, 8.3.2).

#include <algorithm>
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
///
/// Parametrise the incident edge as p(l) = start + l (end - start), l in [0, 1]. Its tangent
/// coordinate d(l) = d0 + l (d1 - d0) is linear, so each side plane cuts it at one l; the kept
/// part is the l-interval inside both planes. One division per plane, no case analysis on which
/// end is outside (the classic Sutherland-Hodgman step written as an interval intersection).
/// Inline: contact_polygons calls it once per touching pair, and a call would store and reload
/// the clipped edge.
[[nodiscard]] inline ClippedEdge clip_incident_edge(const EdgeRef& reference, Vec2 tangent,
                                                    const EdgeRef& incident) noexcept {
  const float lower = dot(tangent, reference.start);
  const float upper = dot(tangent, reference.end);
  const float d0 = dot(tangent, incident.start);
  const float d1 = dot(tangent, incident.end);
  const ContactId start_id{static_cast<std::uint8_t>(reference.index),
                           static_cast<std::uint8_t>(incident.index), FeatureType::edge,
                           FeatureType::vertex};
  const ContactId end_id{static_cast<std::uint8_t>(reference.index),
                         static_cast<std::uint8_t>(incident.next), FeatureType::edge,
                         FeatureType::vertex};
  ClippedEdge out;
  const float span = d1 - d0;
  if (span == 0.0f) {
    // The incident edge is perpendicular to the reference edge: all in or all out.
    if (!(lower <= d0 && d0 <= upper)) return out;
    out.vertices = {ClipVertex{incident.start, start_id}, ClipVertex{incident.end, end_id}};
    out.count = 2;
    return out;
  }
  const float inv = 1.0f / span;
  const float at_lower = (lower - d0) * inv;  // l where the edge crosses the start-side plane
  const float at_upper = (upper - d0) * inv;  // l where it crosses the end-side plane
  // Entering and leaving parameters; which plane is entered first depends on the direction.
  const bool lower_first = at_lower < at_upper;
  const float enter = lower_first ? at_lower : at_upper;
  const float leave = lower_first ? at_upper : at_lower;
  const int enter_vertex = lower_first ? reference.index : reference.next;
  const int leave_vertex = lower_first ? reference.next : reference.index;
  const float l0 = std::max(enter, 0.0f);
  const float l1 = std::min(leave, 1.0f);
  if (!(l0 <= l1)) return out;  // the incident edge lies entirely beside the reference edge
  const Vec2 delta = incident.end - incident.start;
  const ContactId cut_id_enter{static_cast<std::uint8_t>(enter_vertex),
                               static_cast<std::uint8_t>(incident.index), FeatureType::vertex,
                               FeatureType::edge};
  const ContactId cut_id_leave{static_cast<std::uint8_t>(leave_vertex),
                               static_cast<std::uint8_t>(incident.index), FeatureType::vertex,
                               FeatureType::edge};
  out.vertices[0] = l0 > 0.0f ? ClipVertex{incident.start + l0 * delta, cut_id_enter}
                              : ClipVertex{incident.start, start_id};
  out.vertices[1] = l1 < 1.0f ? ClipVertex{incident.start + l1 * delta, cut_id_leave}
                              : ClipVertex{incident.end, end_id};
  out.count = 2;
  return out;
}

}  // namespace collide::detail
