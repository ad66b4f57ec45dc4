// `contact` for every ordered pair of 2D shapes: one dispatch table says which routine serves a
// pair and whether the pair is served in swapped order; swapped pairs are answered by
// `reversed` of the other order, here and nowhere else.

#include <collide/core/error.hpp>
#include <collide/narrow/contact.hpp>
#include <type_traits>

#include "contact_routines.hpp"

namespace collide {
namespace {

enum class Routine : unsigned char { circles, polygon_circle, polygons, polygon_segment };

struct TableEntry {
  Routine routine;
  bool swapped;  ///< served as contact(B, A), then reversed
};

constexpr TableEntry kCircles{Routine::circles, false};
constexpr TableEntry kPolygonCircle{Routine::polygon_circle, false};
constexpr TableEntry kCirclePolygon{Routine::polygon_circle, true};  // served reversed
constexpr TableEntry kPolygons{Routine::polygons, false};
constexpr TableEntry kPolygonSegment{Routine::polygon_segment, false};

// Rows: A's type, columns: B's type, both in ShapeType2D order. Capsules and segments count as
// 2-vertex polygons; as B, they skip building one (contact_polygon_segment).
// clang-format off
constexpr TableEntry kContactTable[4][4] = {
    // B: circle     capsule          polygon         segment
    {kCircles,       kCirclePolygon,  kCirclePolygon, kCirclePolygon},   // A: circle
    {kPolygonCircle, kPolygonSegment, kPolygons,      kPolygonSegment},  // A: capsule
    {kPolygonCircle, kPolygonSegment, kPolygons,      kPolygonSegment},  // A: polygon
    {kPolygonCircle, kPolygonSegment, kPolygons,      kPolygonSegment},  // A: segment
};
// clang-format on

template <class S>
constexpr int type_index() noexcept {
  if constexpr (std::is_same_v<S, Circle>) return 0;
  if constexpr (std::is_same_v<S, Capsule>) return 1;
  if constexpr (std::is_same_v<S, Polygon>) return 2;
  if constexpr (std::is_same_v<S, Segment>) return 3;
}


const Polygon& as_polygon(const Polygon& polygon) noexcept { return polygon; }
Polygon as_polygon(const Capsule& capsule) noexcept {
  return detail::two_vertex_polygon(capsule.a, capsule.b, capsule.radius);
}
Polygon as_polygon(const Segment& segment) noexcept {
  return detail::two_vertex_polygon(segment.a, segment.b, 0.0f);
}
detail::SegmentCore as_segment_core(const Capsule& capsule) noexcept {
  return detail::segment_core(capsule.a, capsule.b, capsule.radius);
}
detail::SegmentCore as_segment_core(const Segment& segment) noexcept {
  return detail::segment_core(segment.a, segment.b, 0.0f);
}

}  // namespace

template <Shape2DType A, Shape2DType B>
Manifold contact(const A& a, const Transform& xa, const B& b, const Transform& xb) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "contact: transform not finite or not unit");
  constexpr TableEntry entry = kContactTable[type_index<A>()][type_index<B>()];
  if constexpr (entry.swapped) {
    Manifold m = contact(b, xb, a, xa);  // built in this function's return slot
    reverse(m);
    return m;
  } else if constexpr (entry.routine == Routine::circles) {
    return detail::contact_circles(a, xa, b, xb);
  } else if constexpr (entry.routine == Routine::polygon_circle) {
    return detail::contact_polygon_circle(as_polygon(a), xa, b, xb);
  } else if constexpr (entry.routine == Routine::polygon_segment) {
    return detail::contact_polygon_segment(as_polygon(a), xa, as_segment_core(b), xb);
  } else {
    return detail::contact_polygons(as_polygon(a), xa, as_polygon(b), xb);
  }
}

Manifold contact(const Shape2D& a, const Transform& xa, const Shape2D& b,
                 const Transform& xb) noexcept {
  return std::visit([&](const auto& sa, const auto& sb) { return contact(sa, xa, sb, xb); }, a, b);
}

// Every ordered pair, so the template's definition can stay in this file.
#define COLLIDE_CONTACT_PAIR(A, B) \
  template Manifold contact<A, B>(const A&, const Transform&, const B&, const Transform&) noexcept;
#define COLLIDE_CONTACT_ROW(A)     \
  COLLIDE_CONTACT_PAIR(A, Circle)  \
  COLLIDE_CONTACT_PAIR(A, Capsule) \
  COLLIDE_CONTACT_PAIR(A, Polygon) \
  COLLIDE_CONTACT_PAIR(A, Segment)
COLLIDE_CONTACT_ROW(Circle)
COLLIDE_CONTACT_ROW(Capsule)
COLLIDE_CONTACT_ROW(Polygon)
COLLIDE_CONTACT_ROW(Segment)
#undef COLLIDE_CONTACT_ROW
#undef COLLIDE_CONTACT_PAIR

}  // namespace collide
