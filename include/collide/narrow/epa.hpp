#pragma once
/// @file
/// Penetration depth of overlapping convex shapes in 3D: EPA, the Expanding Polytope Algorithm
/// (van den Bergen, "Proximity Queries and Penetration Depth Computation on 3D Game Objects",
/// GDC 2001; Collision Detection in Interactive 3D Environments, 2003, 4.3.5).
///
/// When GJK finds the origin inside the Minkowski difference A - B, the penetration depth is
/// the distance from the origin to A - B's boundary, and the direction to the nearest boundary
/// point is the minimum translation: moving B by the depth along it makes the shapes touch.
/// EPA keeps a convex polytope inside A - B that holds the origin (its vertices are support
/// points a - b), starting from GJK's final simplex. Its face nearest the origin gives a lower
/// bound of the depth and a direction n; the support point of A - B along n gives an upper
/// bound. If they differ, that support point joins the polytope (the faces it sees are replaced
/// by a fan from it to their border, the horizon) and the nearest face is looked at again,
/// until the bounds agree within tolerance. The barycentric coordinates of the origin's
/// projection on the final face, applied to the A and B halves of its vertices, give the
/// witness points (the deepest points of each core in the other).
///
/// GJK ends with 1 to 4 vertices. A tetrahedron holds the origin; fewer vertices hold it only
/// within rounding (GJK stops as soon as the origin is on the simplex, which may well be deep
/// inside A - B), so the simplex is grown first: a point by the support point along the axis
/// direction reaching farthest, a segment by the farthest support point perpendicular to it, a
/// triangle by the support points on both sides of its plane (a double pyramid around the
/// origin). Every support value h(d) met on the way bounds the depth from above (depth =
/// min over unit d of h(d)); when one is within rounding of zero the cores touch (A - B is flat
/// there, or the origin is on its boundary) and EPA reports that direction with depth 0, which
/// is also how GJK and EPA agree on the sign near contact. The idea of growing the simplex is
/// Jolt's (EPAPenetrationDepth.h); the storage here is fixed, with no allocation.
///
/// Everything runs in A's frame (B placed by `b_in_a`, as in run_gjk), so pairs far from the
/// origin are as accurate as pairs near it.

#include <collide/core/status.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/core/transform3.hpp>
#include <collide/narrow/gjk.hpp>
#include <collide/narrow/support.hpp>
#include <collide/shape/shape3d.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace collide {

/// Most vertices the EPA polytope holds; each iteration adds one. Convex pairs of boxes,
/// capsules and spheres (A - B has at most 64 vertices) converge in far fewer.
inline constexpr int kEpaMaxVertices = 64;

/// Most faces the EPA polytope holds: a closed triangulated polytope of V vertices has 2 V - 4.
inline constexpr int kEpaMaxFaces = 2 * kEpaMaxVertices;

/// A convex polytope inside A - B, grown by EPA: vertices are simplex vertices (a support point
/// of A and one of B, both in A's frame, and their difference), faces are triangles wound
/// counter-clockwise seen from outside, each with its unit outward normal, its plane's signed
/// distance from the origin, and the face across each edge. Fixed capacity; never allocates.
/// The differences w, which every step reads, are stored apart from the A and B halves, which
/// only the witness points read; a face is 20 bytes (indices fit a byte), and the faces' plane
/// distances one array of their own, which the search for the nearest face reads.
class EpaPolytope {
 public:
  /// Index of a vertex or face slot.
  using Index = std::uint8_t;
  static_assert(kEpaMaxFaces <= 255, "face and vertex indices must fit EpaPolytope::Index");

  /// One triangle of the polytope.
  struct Face {
    Vec3 normal;               ///< unit, outward; zero for a degenerate (zero-area) face
    std::array<Index, 3> v;    ///< vertex indices, counter-clockwise seen from outside
    std::array<Index, 3> adj;  ///< the face across edge k (from v[k] to v[k + 1])
    bool live;                 ///< false once removed (the slot is reused)
  };

  /// Start as triangle (a, b, c) seen from both sides: a flat polytope of two faces. False
  /// (and nothing built) when the triangle has no area.
  bool init_triangle(const GjkVertexN<3>& a, const GjkVertexN<3>& b,
                     const GjkVertexN<3>& c) noexcept;

  /// Start as GJK's tetrahedron (4 vertices), its faces wound outwards. False (and nothing
  /// built) when it has no volume.
  bool init_tetrahedron(const GjkSimplexN<3>& s) noexcept;

  /// Add vertex `w`, which lies in front of face `face`: every face w sees (w in front of its
  /// plane) and connected to `face` is removed, and the hole is closed by a fan of triangles
  /// from w to its border (the horizon). False, with the polytope unchanged, when the vertex
  /// or face capacity would be exceeded or rounding made the border other than one loop.
  bool add(const GjkVertexN<3>& w, int face) noexcept;

  /// The live face whose plane is nearest the origin (smallest distance); -1 if none.
  [[nodiscard]] int closest_face() const noexcept;
  /// The live face that `p` lies farthest in front of (largest normal . (p - vertex)).
  [[nodiscard]] int face_facing(Vec3 p) const noexcept;

  /// Face slot i (check `live`).
  [[nodiscard]] const Face& face(int i) const noexcept { return faces_[i]; }
  /// Face slot i's plane distance from the origin (normal . vertex); +inf for a removed face or
  /// one without area.
  [[nodiscard]] float distance(int i) const noexcept { return distance_[i]; }
  /// Vertex i's point of A - B, i < vertex_count().
  [[nodiscard]] Vec3 point(int i) const noexcept { return w_[i]; }
  /// Vertices added so far (removed faces' vertices stay).
  [[nodiscard]] int vertex_count() const noexcept { return vertex_count_; }

  /// Among the live faces in the plane of face `f` (normals parallel within the sine
  /// kParallelTolerance, plane distances within `tol`), the one whose triangle is nearest the
  /// origin: a face of A - B (a box's face, say) is often several triangles of the polytope,
  /// and the origin projects into only one of them (on a convex polytope around the origin,
  /// the nearest plane's projection lies in the polytope). Other faces with the same plane
  /// distance but another normal are ties of the depth, not candidates.
  [[nodiscard]] int coplanar_face_nearest_origin(int f, float tol) const noexcept;

  /// Witness points of face `i`: the barycentric coordinates of the origin's projection on its
  /// plane, applied to the A and B halves of its vertices (not clamped to the triangle, so
  /// their difference is exactly that projection: distance times normal).
  void witness_points(int i, Vec3& pa, Vec3& pb) const noexcept;

 private:
  /// Store vertex `v` in slot i.
  void set_vertex(int i, const GjkVertexN<3>& v) noexcept;
  /// Fill face slot `f` with triangle (a, b, c): normal and distance from its vertices.
  void set_face(int f, int a, int b, int c) noexcept;
  /// A free face slot (a removed one, else a new one); -1 when full.
  int new_face() noexcept;

  std::array<Vec3, kEpaMaxVertices> w_;   ///< the points of A - B
  std::array<Vec3, kEpaMaxVertices> wa_;  ///< their A halves (A's frame)
  std::array<Vec3, kEpaMaxVertices> wb_;  ///< their B halves (A's frame)
  std::array<Face, kEpaMaxFaces> faces_;
  std::array<float, kEpaMaxFaces> distance_;  ///< per face slot, see distance()
  std::array<Index, kEpaMaxFaces> free_;  ///< removed face slots, reused first
  int vertex_count_ = 0;
  int face_slots_ = 0;  ///< face slots ever used
  int free_count_ = 0;
};

/// Result of run_epa: the penetration of two overlapping cores, A's frame.
struct EpaResult {
  /// overlapped: converged (or the cores touch: depth 0). max_iterations: the polytope's
  /// capacity was reached, or rounding stopped its growth; the fields hold the best estimate
  /// (the nearest face found: its depth is a lower bound).
  QueryStatus status = QueryStatus::overlapped;
  float depth = 0.0f;      ///< penetration depth of the cores, >= 0, world units
  Vec3 normal{0.0f};       ///< unit, from A to B, A's frame: B moved by depth along it touches
  Vec3 point_a{0.0f};      ///< A's core point deepest in B (A's frame)
  Vec3 point_b{0.0f};      ///< B's core point deepest in A: point_a - point_b = depth * normal
  int iterations = 0;      ///< support points evaluated
};

/// EPA (see the file comment) on support maps A and B, B placed in A's frame by `b_in_a`,
/// from GJK's final simplex `simplex` (1..4 vertices, the origin on it within
/// kRelativeTolerance * scale, as run_gjk leaves it when it returns GjkEnd::overlapped).
/// `scale` is the problem's coordinate size in A's frame (gjk_scale): the tolerance of the
/// depth and of touching is kRelativeTolerance * scale. Any two support maps (`SupportMap`);
/// allocates nothing, throws nothing.
template <class PA, class PB>
[[nodiscard]] EpaResult run_epa(const PA& a, const PB& b, const Frame3& b_in_a,
                                const GjkSimplexN<3>& simplex, float scale) noexcept {
  static_assert(SupportMap<PA, 3> && SupportMap<PB, 3>);
  // A tiny problem (below kGjkTinySimplex) runs on A - B scaled by a power of two to unit size:
  // its faces' normals are products of two edges, whose squares underflowed for shapes 2^-40
  // units in size and left every face without a direction (finding 29). Depths are scaled back
  // at the end; the witness points come from the unscaled points of A and B.
  const float sigma = gjk_tiny_simplex_scale(scale);
  const float tol = kRelativeTolerance * scale * sigma;
  // Support values below this count as zero: the origin is within rounding of A - B's
  // boundary (tol from GJK's stop, tol more from the new points' own rounding).
  const float touch = 2.0f * tol;
  EpaResult out;
  const auto support = [&](Vec3 d) {
    ++out.iterations;
    GjkVertexN<3> v = gjk_vertex<3>(a, b, b_in_a, a.support_index(d), b.support_index(inv_rotate(b_in_a, -d)));
    v.w *= sigma;
    return v;
  };
  // The cores touch along `d` (h(d) <= touch): depth 0, witnesses from GJK's simplex.
  const auto touching = [&](Vec3 d) {
    out.status = QueryStatus::overlapped;
    out.depth = 0.0f;
    out.normal = d;
    gjk_witness_points(simplex, out.point_a, out.point_b);
    return out;
  };
  // No polytope could be built (rounding made the start flat; not seen in tests): report the
  // best bound met so far, GJK's witnesses, and that EPA did not converge.
  float best_h = INFINITY;
  Vec3 best_dir = b_in_a.p == Vec3(0.0f) ? Vec3(1, 0, 0) : normalize(b_in_a.p);
  const auto stuck = [&]() {
    out.status = QueryStatus::max_iterations;
    out.depth = best_h < INFINITY ? std::max(best_h, 0.0f) / sigma : 0.0f;
    out.normal = best_dir;
    gjk_witness_points(simplex, out.point_a, out.point_b);
    return out;
  };
  // Among directions whose support value is within `touch` of zero, prefer the one towards B
  // (B's origin in A's frame): ties come from flat or point-like A - B, where every such
  // direction is a valid minimum translation.
  const Vec3 towards_b = b_in_a.p;
  Vec3 touch_dir{0.0f};
  float touch_score = -INFINITY;
  const auto consider = [&](Vec3 d, float h) {
    if (h < best_h) {
      best_h = h;
      best_dir = d;
    }
    if (h <= touch && dot(d, towards_b) > touch_score) {
      touch_dir = d;
      touch_score = dot(d, towards_b);
    }
  };

  // Grow the simplex to a triangle that passes within tol of the origin.
  GjkSimplexN<3> s = simplex;
  for (int i = 0; i < s.count; ++i) s.v[i].w *= sigma;
  while (s.count < 3) {
    // Candidate directions perpendicular to the simplex (a point: the six axis directions).
    std::array<Vec3, 6> dirs{};
    int n = 0;
    if (s.count == 1) {
      dirs = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1),
              Vec3(0, 0, -1)};
      n = 6;
    } else {
      const Vec3 e = s.v[1].w - s.v[0].w;
      const Vec3 ae = collide::abs(e);
      const Vec3 axis = ae.x <= ae.y && ae.x <= ae.z ? Vec3(1, 0, 0)
                        : ae.y <= ae.z               ? Vec3(0, 1, 0)
                                                     : Vec3(0, 0, 1);
      const Vec3 p1 = normalize(cross(e, axis));
      const Vec3 p2 = normalize(cross(e, p1));
      dirs = {p1, -p1, p2, -p2, Vec3(0.0f), Vec3(0.0f)};
      n = 4;
    }
    GjkVertexN<3> far{};
    float far_h = -INFINITY;
    for (int i = 0; i < n; ++i) {
      const GjkVertexN<3> w = support(dirs[i]);
      const float h = dot(dirs[i], w.w);
      consider(dirs[i], h);
      if (h > far_h) {
        far_h = h;
        far = w;
      }
    }
    if (touch_score > -INFINITY) return touching(touch_dir);
    s.v[s.count++] = far;
  }

  EpaPolytope poly;
  if (s.count == 4) {
    // GJK's tetrahedron holds the origin. Flat within rounding: as a triangle and a point in
    // front of one of its sides (add copes with the flat faces that makes).
    if (!poly.init_tetrahedron(s) &&
        (!poly.init_triangle(s.v[0], s.v[1], s.v[2]) ||
         !poly.add(s.v[3], poly.face_facing(s.v[3].w)))) {
      return stuck();
    }
  } else {
    // A triangle within tol of the origin: the support points on both sides of its plane
    // make a double pyramid around it, unless one side is within rounding (touching).
    Vec3 nt = normalize_or_zero(cross(s.v[1].w - s.v[0].w, s.v[2].w - s.v[0].w));
    if (nt == Vec3(0.0f)) nt = Vec3(1, 0, 0);
    const GjkVertexN<3> up = support(nt);
    const GjkVertexN<3> down = support(-nt);
    consider(nt, dot(nt, up.w));
    consider(-nt, -dot(nt, down.w));
    if (touch_score > -INFINITY) return touching(touch_dir);
    if (!poly.init_triangle(s.v[0], s.v[1], s.v[2]) || !poly.add(up, poly.face_facing(up.w)) ||
        !poly.add(down, poly.face_facing(down.w))) {
      return stuck();
    }
  }

  // Expand: the nearest face's distance is a lower bound of the depth, the support value along
  // its normal an upper bound.
  int f = poly.closest_face();
  for (;;) {
    const EpaPolytope::Face& face = poly.face(f);
    const GjkVertexN<3> w = support(face.normal);
    const float h = dot(face.normal, w.w);
    if (h - poly.distance(f) <= tol) break;  // converged
    if (!poly.add(w, f)) {
      out.status = QueryStatus::max_iterations;
      break;
    }
    f = poly.closest_face();
  }
  // The nearest plane may hold several coplanar triangles: report the one the origin projects
  // into, whose barycentric coordinates give the witness points.
  f = poly.coplanar_face_nearest_origin(f, tol);
  const EpaPolytope::Face& face = poly.face(f);
  out.depth = poly.distance(f) > 0.0f ? poly.distance(f) / sigma : 0.0f;
  out.normal = face.normal;
  poly.witness_points(f, out.point_a, out.point_b);
  return out;
}

/// Result of `penetration` in D dimensions (3D for now): the signed depth of two convex
/// shapes and the minimum translation that separates them. World space.
template <int D>
struct PenetrationResultN {
  /// overlapped: the shapes touch or overlap, depth >= 0. separated: they are apart, depth < 0
  /// (minus their distance) and the points are the closest points. max_iterations: GJK or EPA
  /// stopped before converging; the fields hold the best estimate (depth a lower bound).
  QueryStatus status = QueryStatus::separated;
  /// Penetration depth, world units: how far B must move along `normal` to just touch A
  /// (> 0 overlapping, 0 touching); negative when apart: minus the distance.
  float depth = 0.0f;
  /// Unit normal from A to B: the minimum translation direction of B; when apart, the
  /// direction from A's closest point to B's.
  VecN<D> normal{0.0f};
  /// A's surface point deepest inside B (apart: A's closest point to B).
  VecN<D> point_a{0.0f};
  /// B's surface point deepest inside A (apart: B's closest point to A);
  /// point_a - point_b = depth * normal.
  VecN<D> point_b{0.0f};
  int iterations = 0;  ///< support points evaluated by GJK and EPA together
};

using PenetrationResult3 = PenetrationResultN<3>;  ///< 3D penetration result

/// Penetration depth, normal and deepest points of 3D proxies A placed by `xa` and B placed by
/// `xb`: GJK on the cores (gjk.hpp); cores apart give the depth from their distance and the
/// radii (negative when the shapes are apart, and then EPA is not run); cores that overlap go
/// to EPA (run_epa: van den Bergen 2001), whose depth the radii then extend. Works in A's
/// frame. Proxies hold 1..kMaxProxyPoints3 finite points and transforms are finite rigid
/// (COLLIDE_ASSERT). Allocates nothing, throws nothing.
[[nodiscard]] PenetrationResult3 epa_penetration(const ConvexProxy3& a, const Transform3& xa,
                                                 const ConvexProxy3& b,
                                                 const Transform3& xb) noexcept;

/// epa_penetration for two hulls: the same answer, through HullSupportMap (no dispatch on the
/// shape's kind at every support point). Hulls must be valid (make_convex_hull).
[[nodiscard]] PenetrationResult3 epa_penetration(const ConvexHull& a, const Transform3& xa,
                                                 const ConvexHull& b, const Transform3& xb) noexcept;

/// Penetration depth (minimum translation distance), normal from A to B and the deepest points
/// of any two convex 3D shapes, A placed by `xa` and B by `xb`, by GJK and EPA (see
/// `epa_penetration`); world space. The general tool for every convex pair, and the check of
/// `contact`'s specialised routines (their depth and normal agree with it). Swapping A and B
/// flips the normal and swaps the points. Shapes must be valid (make_* functions).
template <Shape3DType A, Shape3DType B>
[[nodiscard]] PenetrationResult3 penetration(const A& a, const Transform3& xa, const B& b,
                                             const Transform3& xb) noexcept {
  if constexpr (std::is_same_v<A, ConvexHull> && std::is_same_v<B, ConvexHull>) {
    return epa_penetration(a, xa, b, xb);
  } else {
    return epa_penetration(ConvexProxy3(a), xa, ConvexProxy3(b), xb);
  }
}

/// `penetration` for 3D shapes whose types are known only at run time.
[[nodiscard]] PenetrationResult3 penetration(const Shape3D& a, const Transform3& xa,
                                             const Shape3D& b, const Transform3& xb) noexcept;

}  // namespace collide
