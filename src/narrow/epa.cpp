#include <collide/narrow/epa.hpp>

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include "penetration_cores.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

namespace collide {

COLLIDE_ALWAYS_INLINE void EpaPolytope::set_vertex(int i, const GjkVertexN<3>& v) noexcept {
  w_[i] = v.w;
  wa_[i] = v.wa;
  wb_[i] = v.wb;
}

COLLIDE_ALWAYS_INLINE void EpaPolytope::set_face(int f, int a, int b, int c) noexcept {
  Face& face = faces_[f];
  face.v = {static_cast<Index>(a), static_cast<Index>(b), static_cast<Index>(c)};
  face.live = true;
  // Component by component: copying the 12-byte points whole made GCC move them through the
  // stack in 8 + 4 byte pieces and read them back across the seam, a failed store forwarding
  // per point (a third of EPA's time on the Jolt-cloud hulls).
  const Vec3 pa{w_[a].x, w_[a].y, w_[a].z};
  const Vec3 pb{w_[b].x, w_[b].y, w_[b].z};
  const Vec3 pc{w_[c].x, w_[c].y, w_[c].z};
  const Vec3 n = cross(pb - pa, pc - pa);
  const float len = length(n);
  if (len > 0.0f) {
    face.normal = n * (1.0f / len);
    // The plane through the three vertices: their mean distance, so no vertex is favoured.
    distance_[f] = (dot(face.normal, pa) + dot(face.normal, pb) + dot(face.normal, pc)) * (1.0f / 3.0f);
  } else {
    // No area: no direction of its own. It is never the nearest face, and the next vertex
    // whose patch reaches it removes it (add); its neighbours carry the polytope's shape.
    face.normal = Vec3(0.0f);
    distance_[f] = INFINITY;
  }
}

COLLIDE_ALWAYS_INLINE int EpaPolytope::new_face() noexcept {
  if (free_count_ > 0) return free_[--free_count_];
  if (face_slots_ == kEpaMaxFaces) return -1;
  return face_slots_++;
}

bool EpaPolytope::init_triangle(const GjkVertexN<3>& a, const GjkVertexN<3>& b,
                                const GjkVertexN<3>& c) noexcept {
  if (!(length_squared(cross(b.w - a.w, c.w - a.w)) > 0.0f)) return false;
  set_vertex(0, a);
  set_vertex(1, b);
  set_vertex(2, c);
  vertex_count_ = 3;
  face_slots_ = 2;
  free_count_ = 0;
  // Face 0 is (0, 1, 2), face 1 the same triangle seen from the other side, (0, 2, 1). Edge k
  // of face 0 runs from v[k] to v[k + 1]; its twin on face 1: 0->1 is edge 2 (1->0), 1->2 is
  // edge 1 (2->1), 2->0 is edge 0 (0->2). Each face is the other's neighbour across every edge.
  set_face(0, 0, 1, 2);
  set_face(1, 0, 2, 1);
  faces_[0].adj = {1, 1, 1};
  faces_[1].adj = {0, 0, 0};
  return true;
}

bool EpaPolytope::init_tetrahedron(const GjkSimplexN<3>& s) noexcept {
  const Vec3 w0 = s.v[0].w;
  const float volume = dot(cross(s.v[1].w - w0, s.v[2].w - w0), s.v[3].w - w0);
  if (!(volume != 0.0f) || !std::isfinite(volume)) return false;
  // Vertex 3 behind face (0, 1, 2): swap 1 and 2 if it is in front.
  const bool flip = volume > 0.0f;
  set_vertex(0, s.v[0]);
  set_vertex(1, s.v[flip ? 2 : 1]);
  set_vertex(2, s.v[flip ? 1 : 2]);
  set_vertex(3, s.v[3]);
  vertex_count_ = 4;
  face_slots_ = 4;
  free_count_ = 0;
  // Face k is opposite vertex 3 - k; each edge appears once in each direction, and adj names
  // the face holding the reverse of edge v[k] -> v[k + 1].
  set_face(0, 0, 1, 2);
  set_face(1, 0, 3, 1);
  set_face(2, 0, 2, 3);
  set_face(3, 1, 3, 2);
  faces_[0].adj = {1, 3, 2};
  faces_[1].adj = {2, 3, 0};
  faces_[2].adj = {0, 3, 1};
  faces_[3].adj = {1, 2, 0};
  return true;
}

int EpaPolytope::closest_face() const noexcept {
  // The first slot holding the smallest distance (removed and flat faces hold +inf).
  int best = -1;
  float best_distance = INFINITY;
  for (int i = 0; i < face_slots_; ++i) {
    if (distance_[i] < best_distance) {
      best = i;
      best_distance = distance_[i];
    }
  }
  // Every face degenerate cannot happen on a polytope with volume; fall back to any live one.
  if (best < 0) {
    for (int i = 0; i < face_slots_ && best < 0; ++i) {
      if (faces_[i].live) best = i;
    }
  }
  return best;
}

int EpaPolytope::face_facing(Vec3 p) const noexcept {
  int best = -1;
  float best_height = -INFINITY;
  for (int i = 0; i < face_slots_; ++i) {
    const Face& f = faces_[i];
    if (!f.live) continue;
    const float height = dot(f.normal, p - w_[f.v[0]]);
    if (height > best_height) {
      best = i;
      best_height = height;
    }
  }
  return best;
}

// Adding a vertex (van den Bergen 2003, 4.3.5): the faces w sees form a connected patch around
// `face` (found by a flood fill over the face adjacency, which keeps it connected even when
// rounding blurs which nearly coplanar faces w sees); their edges whose other face is not seen
// form the horizon, one loop; each horizon edge (a, b) becomes the triangle (a, b, w). Every
// check comes before the first change, so a refusal leaves the polytope as it was.
bool EpaPolytope::add(const GjkVertexN<3>& w, int face) noexcept {
  if (face < 0 || vertex_count_ == kEpaMaxVertices) return false;
  // 1. The visible patch.
  std::array<unsigned char, kEpaMaxFaces> seen{};  // 0 unknown, 1 visible, 2 hidden
  std::array<Index, kEpaMaxFaces> stack;            // NOLINT: filled before read
  std::array<Index, kEpaMaxFaces> patch;            // NOLINT: filled before read
  int stack_size = 0;
  int patch_size = 0;
  seen[face] = 1;
  stack[stack_size++] = static_cast<Index>(face);
  while (stack_size > 0) {
    const int f = stack[--stack_size];
    patch[patch_size++] = static_cast<Index>(f);
    for (int k = 0; k < 3; ++k) {
      const int g = faces_[f].adj[k];
      if (seen[g] != 0) continue;
      const Face& fg = faces_[g];
      // In front of the face's plane. A face without area (three collinear vertices, plane
      // distance infinite: the only live faces with an infinite distance) goes with the patch
      // that reaches it: it covers nothing, and keeping it would leave the fan to fold around it.
      const float plane = distance_[g];
      const bool visible = dot(fg.normal, w.w) > plane || plane == INFINITY;
      seen[g] = visible ? 1 : 2;
      if (visible) stack[stack_size++] = static_cast<Index>(g);
    }
  }
  // 2. The horizon: edges of the patch whose other face is hidden, with that face. Indexed by
  // the edge's first vertex, so that each new triangle finds its neighbours in O(1), and a
  // vertex met twice (a border that is not one loop) is noticed.
  std::array<std::int8_t, kEpaMaxVertices> edge_from;  // horizon edge starting at a vertex
  static_assert(kEpaMaxVertices <= 127, "horizon edge indices must fit edge_from");
  edge_from.fill(-1);
  std::array<Index, kEpaMaxFaces> edge_a;   // NOLINT: filled before read
  std::array<Index, kEpaMaxFaces> edge_b;   // NOLINT
  std::array<Index, kEpaMaxFaces> outside;  // NOLINT
  int edges = 0;
  for (int i = 0; i < patch_size; ++i) {
    const Face& f = faces_[patch[i]];
    for (int k = 0; k < 3; ++k) {
      const int g = f.adj[k];
      if (seen[g] == 1) continue;
      const int a = f.v[k];
      if (edge_from[a] >= 0) return false;  // the border touches itself
      edge_from[a] = static_cast<std::int8_t>(edges);
      edge_a[edges] = static_cast<Index>(a);
      edge_b[edges] = f.v[k == 2 ? 0 : k + 1];
      outside[edges] = static_cast<Index>(g);
      ++edges;
    }
  }
  if (edges < 3) return false;
  // One closed loop: from edge 0, following each edge's end to the edge that starts there
  // comes back to edge 0 after visiting every edge (starts are unique, so this is a
  // permutation; a single cycle means the border is one loop).
  {
    int e = 0;
    int steps = 0;
    do {
      e = edge_from[edge_b[e]];
      if (e < 0) return false;
      ++steps;
    } while (e != 0 && steps <= edges);
    if (e != 0 || steps != edges) return false;
  }
  // Capacity: the patch's slots are freed, one face per horizon edge is needed.
  const int available = (kEpaMaxFaces - face_slots_) + free_count_ + patch_size;
  if (edges > available) return false;

  // 3. Commit: remove the patch, add w, fan from it.
  for (int i = 0; i < patch_size; ++i) {
    faces_[patch[i]].live = false;
    distance_[patch[i]] = INFINITY;  // never the closest face (closest_face reads no `live`)
    free_[free_count_++] = patch[i];
  }
  const int wi = vertex_count_++;
  set_vertex(wi, w);
  std::array<Index, kEpaMaxFaces> made;  // NOLINT: new face of each horizon edge
  for (int e = 0; e < edges; ++e) {
    made[e] = static_cast<Index>(new_face());
    set_face(made[e], edge_a[e], edge_b[e], wi);
  }
  for (int e = 0; e < edges; ++e) {
    Face& nf = faces_[made[e]];
    const int b = edge_b[e];
    // Edge 0 (a -> b): the hidden face beyond the horizon, whose edge b -> a now borders nf
    // (the edge of g that starts at b: g holds each vertex once, and its twin of a -> b).
    const int g = outside[e];
    nf.adj[0] = static_cast<Index>(g);
    Face& fg = faces_[g];
    fg.adj[fg.v[0] == b ? 0 : fg.v[1] == b ? 1 : 2] = made[e];
    // Edge 1 (b -> w): the new face of the horizon edge starting at b (its edge 2, w -> b).
    nf.adj[1] = made[edge_from[b]];
  }
  // Edge 2 (w -> a): the new face of the horizon edge ending at a (its edge 1, a -> w).
  for (int e = 0; e < edges; ++e) {
    faces_[faces_[made[e]].adj[1]].adj[2] = made[e];
  }
  return true;
}

namespace {

/// Barycentric coordinates of the point of triangle (a, b, c) closest to the origin, by its
/// Voronoi regions (Ericson, Real-Time Collision Detection, 5.1.5), and that point's squared
/// distance.
float closest_on_triangle(Vec3 a, Vec3 b, Vec3 c, Vec3& lambda) noexcept {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const float d1 = -dot(ab, a);
  const float d2 = -dot(ac, a);
  if (d1 <= 0.0f && d2 <= 0.0f) {
    lambda = {1.0f, 0.0f, 0.0f};
  } else {
    const float d3 = -dot(ab, b);
    const float d4 = -dot(ac, b);
    const float d5 = -dot(ab, c);
    const float d6 = -dot(ac, c);
    const float vc = d1 * d4 - d3 * d2;
    const float vb = d5 * d2 - d1 * d6;
    const float va = d3 * d6 - d5 * d4;
    if (d3 >= 0.0f && d4 <= d3) {
      lambda = {0.0f, 1.0f, 0.0f};
    } else if (d6 >= 0.0f && d5 <= d6) {
      lambda = {0.0f, 0.0f, 1.0f};
    } else if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
      const float v = d1 / (d1 - d3);
      lambda = {1.0f - v, v, 0.0f};
    } else if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
      const float w = d2 / (d2 - d6);
      lambda = {1.0f - w, 0.0f, w};
    } else if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
      const float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
      lambda = {0.0f, 1.0f - w, w};
    } else {
      const float sum = va + vb + vc;
      if (!(sum > 0.0f)) {
        lambda = {1.0f, 0.0f, 0.0f};
      } else {
        const float inv = 1.0f / sum;
        lambda = {va * inv, vb * inv, vc * inv};
      }
    }
  }
  const Vec3 p = lambda.x * a + lambda.y * b + lambda.z * c;
  return dot(p, p);
}

}  // namespace

int EpaPolytope::coplanar_face_nearest_origin(int f, float tol) const noexcept {
  const Face& ref = faces_[f];
  int best = f;
  Vec3 lambda;
  float best_d2 = -1.0f;  // face f's, measured when a second candidate turns up (most often none)
  for (int i = 0; i < face_slots_; ++i) {
    const Face& g = faces_[i];
    if (i == f || !g.live || !(std::fabs(distance_[i] - distance_[f]) <= tol) ||
        !(dot(g.normal, ref.normal) > 0.0f) ||
        !(length(cross(g.normal, ref.normal)) <= kParallelTolerance)) {
      continue;
    }
    if (best_d2 < 0.0f) best_d2 = closest_on_triangle(w_[ref.v[0]], w_[ref.v[1]], w_[ref.v[2]], lambda);
    const float d2 = closest_on_triangle(w_[g.v[0]], w_[g.v[1]], w_[g.v[2]], lambda);
    if (d2 < best_d2) {
      best = i;
      best_d2 = d2;
    }
  }
  return best;
}

void EpaPolytope::witness_points(int i, Vec3& pa, Vec3& pb) const noexcept {
  const Face& f = faces_[i];
  const int i0 = f.v[0];
  const int i1 = f.v[1];
  const int i2 = f.v[2];
  // The origin's projection on the plane, and its barycentric coordinates from the signed
  // areas of the sub-triangles it makes (Ericson 3.4).
  const Vec3 p = distance_[i] * f.normal;
  const float l0 = dot(cross(w_[i1] - p, w_[i2] - p), f.normal);
  const float l1 = dot(cross(w_[i2] - p, w_[i0] - p), f.normal);
  const float l2 = dot(cross(w_[i0] - p, w_[i1] - p), f.normal);
  const float sum = l0 + l1 + l2;  // twice the area: > 0 for a face with a normal
  if (!(sum > 0.0f)) {
    pa = wa_[i0];
    pb = wb_[i0];
    return;
  }
  const float inv = 1.0f / sum;
  pa = (l0 * inv) * wa_[i0] + (l1 * inv) * wa_[i1] + (l2 * inv) * wa_[i2];
  pb = (l0 * inv) * wb_[i0] + (l1 * inv) * wb_[i1] + (l2 * inv) * wb_[i2];
}

namespace {

/// penetration_of_cores on any two support maps (ConvexProxy3, or HullSupportMap for a pair of
/// hulls, which saves the proxy's dispatch on the shape's kind at every support point).
template <class PA, class PB>
detail::CorePenetration cores_penetration(const PA& a, const Transform3& xa, const PB& b,
                                          const Transform3& xb) noexcept {
  COLLIDE_ASSERT(a.count() >= 1 && b.count() >= 1, "penetration: proxies must hold points");
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "penetration: transforms must be finite rigid");
  const Frame3 b_in_a = to_frame(inv_mul(xa, xb));
  const float ra = a.radius();
  const float rb = b.radius();

  GjkSimplexN<3> s;
  s.v[0] = gjk_seed_vertex<3>(a, b, b_in_a);
  s.count = 1;
  const float scale = gjk_scale<3>(s.v[0], ra + rb);
  detail::CorePenetration route;
  PenetrationResult3& out = route.result;
  int gjk_iterations = 0;
  const GjkEnd end = run_gjk<3>(a, b, b_in_a, s, scale, GjkRunToEnd{}, gjk_iterations);
  out.iterations = gjk_iterations + 1;  // the seed's support evaluation counts too

  Vec3 pa;
  Vec3 pb;
  Vec3 n;
  float depth = 0.0f;
  gjk_witness_points(s, pa, pb);
  const Vec3 delta = pb - pa;
  const float core_distance = length(delta);
  if (end != GjkEnd::overlapped && core_distance > 0.0f) {
    // Cores apart: the radii decide, and GJK and EPA cannot disagree on the sign.
    n = delta * (1.0f / core_distance);
    depth = ra + rb - core_distance;
    out.status = end == GjkEnd::max_iterations ? QueryStatus::max_iterations
                 : depth >= 0.0f               ? QueryStatus::overlapped
                                               : QueryStatus::separated;
  } else {
    route.cores_overlap = true;
    const EpaResult e = run_epa(a, b, b_in_a, s, scale);
    out.iterations += e.iterations;
    out.status = e.status;
    n = e.normal;
    depth = e.depth + ra + rb;
    pa = e.point_a;
    pb = e.point_b;
  }
  out.depth = depth;
  out.normal = rotate(xa.q, n);
  out.point_a = transform_point(xa, pa + ra * n);
  out.point_b = transform_point(xa, pb - rb * n);
  return route;
}

}  // namespace

detail::CorePenetration detail::penetration_of_cores(const ConvexProxy3& a, const Transform3& xa,
                                                     const ConvexProxy3& b,
                                                     const Transform3& xb) noexcept {
  return cores_penetration(a, xa, b, xb);
}

PenetrationResult3 epa_penetration(const ConvexProxy3& a, const Transform3& xa,
                                   const ConvexProxy3& b, const Transform3& xb) noexcept {
  return cores_penetration(a, xa, b, xb).result;
}

PenetrationResult3 epa_penetration(const ConvexHull& a, const Transform3& xa, const ConvexHull& b,
                                   const Transform3& xb) noexcept {
  return cores_penetration(HullSupportMap(a), xa, HullSupportMap(b), xb).result;
}

PenetrationResult3 penetration(const Shape3D& a, const Transform3& xa, const Shape3D& b,
                               const Transform3& xb) noexcept {
  return std::visit(
      [&](const auto& sa, const auto& sb) { return penetration(sa, xa, sb, xb); }, a, b);
}

}  // namespace collide
