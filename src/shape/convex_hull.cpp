#include <collide/shape/convex_hull.hpp>

#include <collide/core/error.hpp>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

namespace collide {
namespace {


// The build runs once per shape, never inside a query, so it may allocate; it runs in double
// (the reason for not using float here): the input floats and their differences are exact in
// double, so orientation tests on nearly coplanar points are decided by the tolerance, not by
// rounding noise.
using DVec3 = glm::dvec3;

/// Passes over all points after quickhull ends, each re-adding points that merges left outside
/// by more than the tolerance (at most two were needed on all test clouds; see run()).
constexpr int kMaxSweeps = 4;

/// Bound, in FLT_EPSILON units of |q|1 + max |offset|, on the rounding of a point's height above
/// a plane computed in float by the sweep's pre-pass (the offset's conversion, three products,
/// two sums, one difference: within 2 of those units together; twice that for margin).
constexpr double kSweepFloatErrorUlps = 4.0;
/// The pre-pass is used where |q|1 + max |offset| stays below this (sums of such terms cannot
/// overflow a float); points farther out take the exact loop alone.
constexpr double kSweepFloatRange = 1e30;

/// Bound on the length of a stored (float) unit normal: each component within half a float ulp
/// of the double one's (1 + 2^-24 at most; this leaves room).
constexpr double kSweepNormalLength = 1.0 + 1e-6;
/// Bound, in DBL_EPSILON units of |q|1 + |c|1 + max |offset|, on the rounding of the sweep's
/// inner-ball test and of the exact heights it stands in for (a few ulps each; far more here).
constexpr double kSweepBallRoundingUlps = 1e4;

/// Two neighbouring faces merge when the corners of their union spread less than this fraction
/// of the tolerance about its plane. Below 1 so that the merges a concave edge forces (after
/// another merge tilted a plane) still leave every face planar within the tolerance: with 1,
/// such merges reached 1.09 tolerances on random flat clouds.
constexpr double kCoplanarFraction = 0.5;

/// is_thin's area test passes a face as wide only when its area exceeds the tolerance times
/// its diameter bound by this factor: far above the rounding of either (about 1e-15 relative),
/// so the test never passes a face the side-by-corner loop would find thin.
constexpr double kThinTestMargin = 1.0 + 1e-6;

/// The points' worth of arrays the per-thread builder keeps between builds (a few MiB: a
/// point's arrays take about 40 bytes, a face's and half-edge's more).
constexpr std::size_t kKeptBuilderPoints = std::size_t{1} << 16;

/// Thrown inside the builder when a merge would fold the hull flat: leave a face of fewer than
/// three sides, or join a face to itself. Merging within the tolerance can do that to a cloud
/// that passed build_initial's thickness test but is a needle or sliver only a few tolerances
/// across (fuzz_shapes found one 184,536 long and 16 wide, tolerance 1.8): the merges went on
/// through freed half-edges and read faces_[-1]. make_convex_hull reports it as InvalidInput.
struct FoldedFlat {};

/// A half-edge of the hull under construction (indices into the builder's arrays).
struct HalfEdge {
  int origin = -1;  ///< point index where the half-edge starts
  int twin = -1;    ///< the opposite half-edge, in the neighbouring face
  int next = -1;    ///< next half-edge counter-clockwise around `face`
  int prev = -1;    ///< previous half-edge around `face`
  int face = -1;    ///< face on the left (seen from outside)
};

/// A face of the hull under construction: a convex polygon with its plane and outside set.
struct BuildFace {
  DVec3 normal{0.0};    ///< unit outward normal (Newell); zero for a degenerate face
  /// `normal` rounded to float once, as the hull stores it. Kept rather than rounded where
  /// used: GCC 12.2's SLP vectorizer at -O2 folds DVec3(Vec3(normal)) back to `normal` for x
  /// and y (wrong code), which made the sweep and the stored planes disagree by an ulp.
  Vec3 stored_normal{0.0f};
  DVec3 centroid{0.0};  ///< average of the corners
  DVec3 area_vector{0.0};  ///< Newell's vector: twice the area times the normal
  double offset = 0.0;  ///< dot(normal, centroid)
  double area = 0.0;
  int edge = -1;        ///< one half-edge of the face
  bool alive = false;
  bool visible = false;  ///< seen by the current eye point (valid when mark == stamp)
  bool queued = false;   ///< in the merge work list
  int mark = 0;          ///< stamp of the last visibility test
  /// Conflict list: the points above this face by more than the tolerance, in the order they
  /// were added, linked through QuickHull::next_outside_ (a point is in one list at a time).
  int first_outside = -1;
  int last_outside = -1;
  int furthest = -1;         ///< the outside point farthest above the plane (see furthest_)
  /// QuickHull::changes_ when merge_step last found this face to merge with none of its
  /// neighbours (kNeverClean: not since it was made).
  std::uint64_t clean_at = 0;
};

/// BuildFace::clean_at of a face not yet found clean.
constexpr std::uint64_t kNeverClean = ~std::uint64_t{0};

/// The run of consecutive edges two faces share, as seen from face f: half-edges first..last
/// of f (whose twins lie in g), the edge p of f before the run and n after it, and the edges
/// of g that continue from the run's start (m) and lead into its end (q).
struct SharedRun {
  int first, last, p, n, m, q;
};

/// One builder per thread, kept between builds (make_convex_hull): every array keeps its
/// capacity, so a build allocates only the hull it returns (on Jolt's clouds 49 allocations a
/// hull before, 9 after). A build that leaves arrays past kKeptBuilderPoints points' worth gives
/// them back.
class QuickHull {
 public:
  /// Starts a build of `input` around `origin` (the points are taken relative to it).
  void reset(std::span<const Vec3> input, DVec3 origin, double tolerance, int max_vertices) {
    input_ = input;
    origin_ = origin;
    tol_ = tolerance;
    pts_.clear();
    for (const Vec3& p : input) pts_.push_back(DVec3(p) - origin);
    vertex_mark_.assign(pts_.size(), 0);
    next_outside_.assign(pts_.size(), -1);
    edges_.clear();
    free_edges_.clear();
    faces_.clear();
    furthest_.clear();
    free_faces_.clear();
    stamp_ = 0;
    vertex_stamp_ = 0;
    changes_ = 0;
    added_ = 0;
    swept_offset_.clear();
    swept_ = false;
    // A hull of V vertices has at most 2V - 4 faces and 6V - 12 half-edges; a few spare for
    // the cone being built while the visible faces still exist.
    const size_t v = std::min(pts_.size(), static_cast<size_t>(max_vertices));
    faces_.reserve(3 * v);
    furthest_.reserve(3 * v);
    edges_.reserve(9 * v);
  }
  /// Gives back the arrays' memory when a build left them larger than kKeptBuilderPoints
  /// points need.
  void trim() {
    if (pts_.capacity() > kKeptBuilderPoints) *this = QuickHull{};
  }

  /// Builds the initial tetrahedron; returns nullptr or the degeneracy it found.
  const char* build_initial();
  /// How run() ended.
  enum class Outcome {
    verified,    ///< no point is left outside: a sweep over all of them found none
    unverified,  ///< kMaxSweeps sweeps each put points back (never seen on test clouds)
    capped,      ///< stopped at max_vertices with points outside
  };
  /// Adds outside points, farthest first, until none is left or the hull has max_vertices.
  Outcome run(int max_vertices);
  /// Writes the result into `hull`. `contain_inputs`: raise each face's offset so that every
  /// input point lies within the tolerance below it.
  void extract(bool contain_inputs, ConvexHull& hull);

 private:
  [[nodiscard]] double distance(int f, const DVec3& p) const {
    return glm::dot(faces_[f].normal, p) - faces_[f].offset;
  }
  [[nodiscard]] int end_of(int h) const { return edges_[edges_[h].twin].origin; }
  /// Appends `point` to face f's conflict list.
  void push_outside(int f, int point) {
    next_outside_[point] = -1;
    if (faces_[f].last_outside < 0) {
      faces_[f].first_outside = point;
    } else {
      next_outside_[faces_[f].last_outside] = point;
    }
    faces_[f].last_outside = point;
  }
  /// Calls visit(point) for each point of face f's conflict list, in order.
  template <class Visit>
  void for_each_outside(int f, Visit&& visit) const {
    for (int p = faces_[f].first_outside; p >= 0; p = next_outside_[p]) visit(p);
  }
  void clear_outside(int f) { faces_[f].first_outside = faces_[f].last_outside = -1; }
  int new_edge(int origin, int face);
  int new_face();
  void free_edge(int h);
  void free_face(int f);
  int make_triangle(int a, int b, int c);
  void compute_plane(int f);
  [[nodiscard]] int edge_count(int f) const;
  void assign(int point, std::span<const int> candidates);
  void add_point(int eye, int seed);
  void find_horizon(int eye, int f, int entry);
  [[nodiscard]] bool horizon_is_loop();
  template <class Stop>
  [[nodiscard]] std::pair<double, double> union_heights(int f, int g, const DVec3& direction, Stop&& stop) const;
  [[nodiscard]] double union_spread(int f, int g) const;
  [[nodiscard]] bool union_within(int f, int g, double limit) const;
  [[nodiscard]] bool should_merge(int f, int h) const;
  [[nodiscard]] SharedRun shared_run(int f, int h) const;
  [[nodiscard]] bool shares_one_run(int f, int h) const;
  [[nodiscard]] double corner_turn(int a, int b, int c, const DVec3& normal) const;
  [[nodiscard]] bool is_thin(int f) const;
  bool merge_step(int f);
  void merge(int f, int h);
  void fix_degree_two_vertices(int f);
  void enqueue(int f);
  [[nodiscard]] int vertex_count();
  /// The face whose farthest outside point is farthest above it (the first such slot), or -1
  /// when no face has one.
  [[nodiscard]] int farthest_face() const;
  bool sweep_outside_points();

  std::span<const Vec3> input_;  ///< the points as given
  std::vector<DVec3> pts_;  ///< input points minus origin_
  DVec3 origin_{0.0};       ///< the local origin the build works around
  double tol_ = 0.0;
  std::vector<HalfEdge> edges_;
  std::vector<int> free_edges_;
  std::vector<BuildFace> faces_;
  std::vector<double> furthest_;  ///< per face slot: distance of its farthest outside point, 0
                                  ///< when it has none or is dead (dense: scanned per point)
  std::vector<int> free_faces_;
  std::vector<int> vertex_mark_;
  std::vector<int> next_outside_;  ///< per point: the next point of its conflict list, or -1
  int stamp_ = 0;
  int vertex_stamp_ = 0;
  /// Counts the changes to the hull's faces (a plane worked out, a face merged or freed):
  /// merge_step's answers hold until it moves.
  std::uint64_t changes_ = 0;
  int added_ = 0;  ///< points added after the initial tetrahedron
  /// Per face slot: the stored plane's offset (through the farthest vertex, input coordinates)
  /// as the last sweep computed it; valid for extract() when that sweep found nothing.
  std::vector<double> swept_offset_;
  std::vector<float> sweep_planes_;  ///< the sweep's planes as float: normals x, y, z, offsets
  bool swept_ = false;
  // Scratch of add_point, kept to reuse capacity.
  std::vector<int> horizon_;
  std::vector<int> visible_;
  std::vector<int> orphans_;
  std::vector<int> work_;
  // Scratch of sweep_outside_points and extract.
  std::vector<int> sweep_vertices_;
  std::vector<int> sweep_faces_;
  std::vector<DVec3> sweep_normals_;
  std::vector<double> sweep_vertex_coords_;  ///< the hull's vertices, x then y then z arrays
  std::vector<int> index_of_;
  std::vector<int> point_of_;
  std::vector<int> face_of_;
  std::vector<int> live_;
  std::vector<int> edge_of_;
  std::vector<int> fill_;
};

int QuickHull::new_edge(int origin, int face) {
  int h;
  if (!free_edges_.empty()) {
    h = free_edges_.back();
    free_edges_.pop_back();
  } else {
    h = static_cast<int>(edges_.size());
    edges_.emplace_back();
  }
  edges_[h] = HalfEdge{origin, -1, -1, -1, face};
  return h;
}

int QuickHull::new_face() {
  int f;
  if (!free_faces_.empty()) {
    f = free_faces_.back();
    free_faces_.pop_back();
  } else {
    f = static_cast<int>(faces_.size());
    faces_.emplace_back();
    furthest_.push_back(0.0);
  }
  BuildFace& face = faces_[f];
  face.alive = true;
  face.visible = false;
  face.queued = false;
  face.mark = 0;
  face.clean_at = kNeverClean;
  clear_outside(f);
  face.furthest = -1;
  furthest_[f] = 0.0;
  return f;
}

void QuickHull::free_edge(int h) {
  edges_[h].face = -1;
  free_edges_.push_back(h);
}

void QuickHull::free_face(int f) {
  ++changes_;
  faces_[f].alive = false;
  furthest_[f] = 0.0;
  faces_[f].edge = -1;
  free_faces_.push_back(f);
}

int QuickHull::make_triangle(int a, int b, int c) {
  const int f = new_face();
  const int e0 = new_edge(a, f);
  const int e1 = new_edge(b, f);
  const int e2 = new_edge(c, f);
  edges_[e0].next = e1;
  edges_[e1].next = e2;
  edges_[e2].next = e0;
  edges_[e0].prev = e2;
  edges_[e1].prev = e0;
  edges_[e2].prev = e1;
  faces_[f].edge = e0;
  return f;
}

int QuickHull::edge_count(int f) const {
  int n = 0;
  int h = faces_[f].edge;
  do {
    ++n;
    h = edges_[h].next;
  } while (h != faces_[f].edge);
  return n;
}

// Plane of a polygon by Newell's method (the area vector, exact for planar polygons and a
// least-squares-like average otherwise), through the average of its corners.
void QuickHull::compute_plane(int f) {
  ++changes_;
  BuildFace& face = faces_[f];
  const DVec3 ref = pts_[edges_[face.edge].origin];
  DVec3 n{0.0};
  DVec3 sum{0.0};
  int count = 0;
  int h = face.edge;
  do {
    const DVec3 a = pts_[edges_[h].origin] - ref;
    const DVec3 b = pts_[edges_[edges_[h].next].origin] - ref;
    n += glm::cross(a, b);
    sum += a;
    ++count;
    h = edges_[h].next;
  } while (h != face.edge);
  const double len = glm::length(n);
  face.area = 0.5 * len;
  face.area_vector = n;
  face.normal = len > 0.0 ? n / len : DVec3{0.0};
  face.stored_normal = Vec3(face.normal);
  face.centroid = ref + sum / static_cast<double>(count);
  face.offset = glm::dot(face.normal, face.centroid);
}

const char* QuickHull::build_initial() {
  const int n = static_cast<int>(pts_.size());
  // The extreme points along the axes; the farthest pair of them spans the first edge.
  // (The extremes' coordinates are kept beside their indices: read back through the index,
  // each comparison waited on the load the last new extreme started.)
  int extreme[6] = {0, 0, 0, 0, 0, 0};
  DVec3 least = pts_[0];
  DVec3 most = pts_[0];
  for (int i = 1; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double c = pts_[i][k];
      if (c < least[k]) {
        least[k] = c;
        extreme[2 * k] = i;
      }
      if (c > most[k]) {
        most[k] = c;
        extreme[2 * k + 1] = i;
      }
    }
  }
  int i0 = extreme[0];
  int i1 = extreme[1];
  double best = -1.0;
  for (int a = 0; a < 6; ++a) {
    for (int b = a + 1; b < 6; ++b) {
      const DVec3 d = pts_[extreme[b]] - pts_[extreme[a]];
      const double len2 = glm::dot(d, d);
      if (len2 > best) {
        best = len2;
        i0 = extreme[a];
        i1 = extreme[b];
      }
    }
  }
  if (std::sqrt(best) <= tol_) return "all coincident";
  // The point farthest from the line i0 i1.
  const DVec3 axis = glm::normalize(pts_[i1] - pts_[i0]);
  int i2 = -1;
  best = -1.0;
  for (int i = 0; i < n; ++i) {
    const DVec3 d = pts_[i] - pts_[i0];
    const DVec3 off = d - axis * glm::dot(d, axis);
    const double dist2 = glm::dot(off, off);
    if (dist2 > best) {
      best = dist2;
      i2 = i;
    }
  }
  if (std::sqrt(best) <= tol_) return "collinear";
  // The point farthest from the plane i0 i1 i2, on either side. The cloud's thickness across
  // that plane must exceed a few tolerances: a thinner hull would have side faces no wider
  // than the tolerance, which the merging would fold flat.
  const DVec3 normal =
      glm::normalize(glm::cross(pts_[i1] - pts_[i0], pts_[i2] - pts_[i0]));
  int i3 = -1;
  double lo = 0.0;
  double hi = 0.0;
  best = -1.0;
  for (int i = 0; i < n; ++i) {
    const double d = glm::dot(normal, pts_[i] - pts_[i0]);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
    if (std::fabs(d) > best) {
      best = std::fabs(d);
      i3 = i;
    }
  }
  if (hi - lo <= static_cast<double>(kHullFlatFactor) * tol_) return "coplanar";

  // Orient so that i3 lies behind the face (i0, i1, i2).
  if (glm::dot(normal, pts_[i3] - pts_[i0]) > 0.0) std::swap(i1, i2);
  const int a = i0, b = i1, c = i2, d = i3;
  const int tri[4][3] = {{a, b, c}, {b, a, d}, {c, b, d}, {a, c, d}};
  int made[4];
  for (int k = 0; k < 4; ++k) made[k] = make_triangle(tri[k][0], tri[k][1], tri[k][2]);
  // Link twins: each directed edge u -> v meets v -> u in another face.
  for (int f1 : made) {
    int h1 = faces_[f1].edge;
    do {
      if (edges_[h1].twin < 0) {
        const int u = edges_[h1].origin;
        const int v = edges_[edges_[h1].next].origin;
        for (int f2 : made) {
          if (f2 == f1) continue;
          int h2 = faces_[f2].edge;
          do {
            if (edges_[h2].origin == v && edges_[edges_[h2].next].origin == u) {
              edges_[h1].twin = h2;
              edges_[h2].twin = h1;
            }
            h2 = edges_[h2].next;
          } while (h2 != faces_[f2].edge);
        }
      }
      h1 = edges_[h1].next;
    } while (h1 != faces_[f1].edge);
  }
  for (int f : made) compute_plane(f);
  for (int i = 0; i < n; ++i) {
    if (i == a || i == b || i == c || i == d) continue;
    assign(i, made);
  }
  return nullptr;
}

// Puts `point` into the outside set of the candidate face it is farthest above, if it is above
// one by more than the tolerance; otherwise it is inside (or on) the hull and dropped.
void QuickHull::assign(int point, std::span<const int> candidates) {
  int best_face = -1;
  double best = tol_;
  for (int f : candidates) {
    if (!faces_[f].alive) continue;
    const double d = distance(f, pts_[point]);
    if (d > best) {
      best = d;
      best_face = f;
    }
  }
  if (best_face < 0) return;
  BuildFace& face = faces_[best_face];
  push_outside(best_face, point);
  if (best > furthest_[best_face]) {
    furthest_[best_face] = best;
    face.furthest = point;
  }
}

int QuickHull::vertex_count() {
  ++vertex_stamp_;
  int count = 0;
  for (const HalfEdge& e : edges_) {
    if (e.face < 0) continue;
    if (vertex_mark_[e.origin] != vertex_stamp_) {
      vertex_mark_[e.origin] = vertex_stamp_;
      ++count;
    }
  }
  return count;
}

// The largest of furthest_ in lanes (two pairs at a time), then its first slot: the first face
// with the farthest outside point, as one pass keeping the first strictly larger value finds it
// (a pass with a branch on every slot, a tenth of a 1000-point build).
int QuickHull::farthest_face() const {
  const double* value = furthest_.data();
  const size_t n = furthest_.size();
  __m128d low = _mm_set1_pd(tol_);
  __m128d high = low;
  size_t k = 0;
  for (; k + 4 <= n; k += 4) {
    low = _mm_max_pd(low, _mm_loadu_pd(value + k));
    high = _mm_max_pd(high, _mm_loadu_pd(value + k + 2));
  }
  low = _mm_max_pd(low, high);
  double best = std::max(_mm_cvtsd_f64(low), _mm_cvtsd_f64(_mm_unpackhi_pd(low, low)));
  for (; k < n; ++k) best = std::max(best, value[k]);
  if (!(best > tol_)) return -1;
  k = 0;
  while (value[k] != best) ++k;
  return static_cast<int>(k);
}

QuickHull::Outcome QuickHull::run(int max_vertices) {
  for (int sweep = 0;; ++sweep) {
    for (;;) {
      const int seed = farthest_face();
      if (seed < 0) break;
      // Counting vertices walks all edges: only once the cap is within reach.
      if (added_ + 4 >= max_vertices && vertex_count() >= max_vertices) return Outcome::capped;
      add_point(faces_[seed].furthest, seed);
      ++added_;
    }
    if (sweep == kMaxSweeps) return Outcome::unverified;
    if (!sweep_outside_points()) {
      swept_ = true;
      return Outcome::verified;
    }
  }
}

// Merges tilt planes after points were dropped as within the tolerance of a face, so one pass
// checks every point against the planes the hull will be stored with (the float normal, the
// offset through the farthest vertex, evaluated on the input coordinates as extract() does)
// and puts any point more than the tolerance above one back into play. Returns whether it
// found any.
bool QuickHull::sweep_outside_points() {
  std::vector<int>& vertices = sweep_vertices_;
  vertices.clear();
  ++vertex_stamp_;
  for (const HalfEdge& e : edges_) {
    if (e.face >= 0 && vertex_mark_[e.origin] != vertex_stamp_) {
      vertex_mark_[e.origin] = vertex_stamp_;
      vertices.push_back(e.origin);
    }
  }
  std::vector<int>& alive = sweep_faces_;
  alive.clear();
  std::vector<DVec3>& normal = sweep_normals_;
  normal.clear();
  swept_offset_.assign(faces_.size(), 0.0);
  // The vertices in double, one array per coordinate (padded to pairs by repeating the first),
  // so that each plane's farthest vertex is found two vertices at a time: the same products and
  // sums, in the same order, as glm::dot (n.x v.x + n.y v.y) + n.z v.z.
  const size_t pairs = (vertices.size() + 1) / 2 * 2;
  std::vector<double>& vx = sweep_vertex_coords_;
  vx.resize(3 * pairs);
  double* vy = vx.data() + pairs;
  double* vz = vy + pairs;
  for (size_t k = 0; k < pairs; ++k) {
    const DVec3 v(input_[vertices[k < vertices.size() ? k : 0]]);
    vx[k] = v.x;
    vy[k] = v.y;
    vz[k] = v.z;
  }
  for (int f = 0; f < static_cast<int>(faces_.size()); ++f) {
    if (!faces_[f].alive) continue;
    alive.push_back(f);
    const DVec3 n(faces_[f].stored_normal);
    const __m128d nx2 = _mm_set1_pd(n.x), ny2 = _mm_set1_pd(n.y), nz2 = _mm_set1_pd(n.z);
    __m128d top2 = _mm_set1_pd(-HUGE_VAL);
    for (size_t k = 0; k < pairs; k += 2) {
      const __m128d d = _mm_add_pd(_mm_add_pd(_mm_mul_pd(nx2, _mm_loadu_pd(vx.data() + k)),
                                              _mm_mul_pd(ny2, _mm_loadu_pd(vy + k))),
                                   _mm_mul_pd(nz2, _mm_loadu_pd(vz + k)));
      top2 = _mm_max_pd(d, top2);  // d only when greater: std::max(top, d)
    }
    double top = std::max(_mm_cvtsd_f64(top2), _mm_cvtsd_f64(_mm_unpackhi_pd(top2, top2)));
    if (top == 0.0) {
      // Equal non-zero doubles have equal bits, so the order the pairs were taken in cannot
      // change a non-zero maximum; at zero it picks the sign: the first vertex's, as one pass
      // in order takes it.
      top = -HUGE_VAL;
      for (int v : vertices) top = std::max(top, glm::dot(n, DVec3(input_[v])));
    }
    normal.push_back(n);
    swept_offset_[f] = top;
  }
  // An inner ball settles the points deep inside at once: from the vertices' mean c, every
  // stored plane is at least r = min (offset - n . c) away, so a point p has a height of at most
  // |n| |p - c| - r above each. Where that bound, with the exact loop's rounding
  // (kSweepBallRoundingUlps double ulps of the magnitudes), stays within the tolerance, the exact
  // loop below would find no height above it: the point is skipped with the same outcome.
  DVec3 centre{0.0};
  for (size_t k = 0; k < vertices.size(); ++k) centre += DVec3(vx[k], vy[k], vz[k]);
  centre /= static_cast<double>(vertices.size());
  double clearance = HUGE_VAL;
  for (size_t k = 0; k < alive.size(); ++k) {
    clearance = std::min(clearance, swept_offset_[alive[k]] - glm::dot(normal[k], centre));
  }
  const double centre_magnitude = std::abs(centre.x) + std::abs(centre.y) + std::abs(centre.z);
  // A float pre-pass, four planes at a time, settles most points: the largest height above the
  // planes in float, when below the tolerance by more than its rounding error, proves the
  // exact (double) heights are too. Planes padded to a multiple of four never win.
  const size_t lanes = (alive.size() + 3) / 4 * 4;
  sweep_planes_.assign(4 * lanes, 0.0f);
  float* nx = sweep_planes_.data();
  float* ny = nx + lanes;
  float* nz = ny + lanes;
  float* off = nz + lanes;
  double max_offset = 0.0;
  for (size_t k = 0; k < lanes; ++k) {
    if (k < alive.size()) {
      const Vec3& n = faces_[alive[k]].stored_normal;
      nx[k] = n.x;
      ny[k] = n.y;
      nz[k] = n.z;
      const double offset = std::clamp(swept_offset_[alive[k]], -kSweepFloatRange, kSweepFloatRange);
      off[k] = static_cast<float>(offset);
      max_offset = std::max(max_offset, std::abs(swept_offset_[alive[k]]));
    } else {
      off[k] = FLT_MAX;  // height -FLT_MAX: never the largest
    }
  }
  bool any = false;
  for (int i = 0; i < static_cast<int>(pts_.size()); ++i) {
    if (vertex_mark_[i] == vertex_stamp_) continue;
    const Vec3& q = input_[i];
    // Rounding of a height in float: the offset's conversion, three products, two sums and
    // the difference, each within half an ulp of a magnitude at most |q|1 + |offset| (|n| <= 1
    // per component), so within kSweepFloatErrorUlps ulps of that together. Beyond
    // kSweepFloatRange (nothing a hull of a game's shapes holds) float could overflow: exact only.
    const double magnitude = std::abs(static_cast<double>(q.x)) + std::abs(static_cast<double>(q.y)) +
                             std::abs(static_cast<double>(q.z)) + max_offset;
    {
      const DVec3 away = DVec3(q) - centre;
      const double rounding = kSweepBallRoundingUlps * DBL_EPSILON * (magnitude + centre_magnitude);
      const double reach = (clearance + tol_ - rounding) / kSweepNormalLength;
      if (reach > 0.0 && glm::dot(away, away) <= reach * reach) continue;
    }
    if (magnitude <= kSweepFloatRange) {
      const __m128 qx = _mm_set1_ps(q.x), qy = _mm_set1_ps(q.y), qz = _mm_set1_ps(q.z);
      __m128 top4 = _mm_set1_ps(-FLT_MAX);
      for (size_t k = 0; k < lanes; k += 4) {
        const __m128 h = _mm_sub_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_loadu_ps(nx + k), qx),
                                                          _mm_mul_ps(_mm_loadu_ps(ny + k), qy)),
                                               _mm_mul_ps(_mm_loadu_ps(nz + k), qz)),
                                    _mm_loadu_ps(off + k));
        top4 = _mm_max_ps(top4, h);
      }
      top4 = _mm_max_ps(top4, _mm_shuffle_ps(top4, top4, _MM_SHUFFLE(1, 0, 3, 2)));
      top4 = _mm_max_ps(top4, _mm_shuffle_ps(top4, top4, _MM_SHUFFLE(2, 3, 0, 1)));
      const double error = kSweepFloatErrorUlps * static_cast<double>(FLT_EPSILON) * magnitude;
      if (static_cast<double>(_mm_cvtss_f32(top4)) + error <= tol_) continue;
    }
    const DVec3 p(q);
    int best_face = -1;
    double best = tol_;
    for (size_t k = 0; k < alive.size(); ++k) {
      const double d = glm::dot(normal[k], p) - swept_offset_[alive[k]];
      if (d > best) {
        best = d;
        best_face = alive[k];
      }
    }
    if (best_face >= 0) {
      any = true;
      BuildFace& face = faces_[best_face];
      push_outside(best_face, i);
      if (best > furthest_[best_face]) {
        furthest_[best_face] = best;
        face.furthest = i;
      }
    }
  }
  return any;
}

// Depth-first search over the faces the eye sees, walking each face's edges in order from the
// one it was entered by: the edges into unseen faces come out as the horizon, in order
// counter-clockwise around the visible region (Barber et al. 1996; Gregorius 2014).
void QuickHull::find_horizon(int eye, int f, int entry) {
  faces_[f].mark = stamp_;
  faces_[f].visible = true;
  visible_.push_back(f);
  const int stop = entry < 0 ? faces_[f].edge : entry;
  int h = entry < 0 ? faces_[f].edge : edges_[entry].next;
  do {
    const int t = edges_[h].twin;
    const int g = edges_[t].face;
    if (faces_[g].mark != stamp_) {
      if (distance(g, pts_[eye]) > 0.0) {
        find_horizon(eye, g, t);
      } else {
        faces_[g].mark = stamp_;
        faces_[g].visible = false;
        horizon_.push_back(h);
      }
    } else if (!faces_[g].visible) {
      horizon_.push_back(h);
    }
    h = edges_[h].next;
  } while (h != stop);
}

// The horizon must be one simple closed loop (the visible faces form a disc); tolerance-level
// disagreements between neighbouring faces could in principle break that.
bool QuickHull::horizon_is_loop() {
  const size_t k = horizon_.size();
  if (k < 3) return false;
  ++vertex_stamp_;
  for (size_t i = 0; i < k; ++i) {
    const int h = horizon_[i];
    if (end_of(h) != edges_[horizon_[(i + 1) % k]].origin) return false;
    if (vertex_mark_[edges_[h].origin] == vertex_stamp_) return false;
    vertex_mark_[edges_[h].origin] = vertex_stamp_;
  }
  return true;
}

void QuickHull::enqueue(int f) {
  if (!faces_[f].queued) {
    faces_[f].queued = true;
    work_.push_back(f);
  }
}

void QuickHull::add_point(int eye, int seed) {
  ++stamp_;
  horizon_.clear();
  visible_.clear();
  find_horizon(eye, seed, -1);
  if (!horizon_is_loop()) {
    // Never seen on the test clouds; dropping the eye keeps the topology valid and leaves the
    // point outside by at most a few tolerances (it was seen ambiguously by a coplanar face).
    const int first = faces_[seed].first_outside;
    clear_outside(seed);
    faces_[seed].furthest = -1;
    furthest_[seed] = 0.0;
    for (int p = first; p >= 0;) {
      const int next = next_outside_[p];
      if (p != eye) {
        push_outside(seed, p);
        const double d = distance(seed, pts_[p]);
        if (d > furthest_[seed]) {
          furthest_[seed] = d;
          faces_[seed].furthest = p;
        }
      }
      p = next;
    }
    return;
  }

  // The cone of new triangles from the horizon to the eye.
  work_.clear();
  const size_t k = horizon_.size();
  int first_new = -1;
  int prev_new = -1;
  for (size_t i = 0; i < k; ++i) {
    const int h = horizon_[i];
    const int t = edges_[h].twin;
    const int f = make_triangle(edges_[h].origin, end_of(h), eye);
    const int e0 = faces_[f].edge;  // origin -> end, twin of the unseen face's edge
    edges_[e0].twin = t;
    edges_[t].twin = e0;
    if (prev_new >= 0) {
      const int b_to_eye = edges_[faces_[prev_new].edge].next;
      const int eye_to_a = edges_[e0].prev;
      edges_[b_to_eye].twin = eye_to_a;
      edges_[eye_to_a].twin = b_to_eye;
    } else {
      first_new = f;
    }
    prev_new = f;
    compute_plane(f);
    enqueue(f);
  }
  {
    const int b_to_eye = edges_[faces_[prev_new].edge].next;
    const int eye_to_a = edges_[faces_[first_new].edge].prev;
    edges_[b_to_eye].twin = eye_to_a;
    edges_[eye_to_a].twin = b_to_eye;
  }

  // Remove the visible faces; their outside points are orphans until reassigned.
  orphans_.clear();
  for (int f : visible_) {
    for_each_outside(f, [&](int p) {
      if (p != eye) orphans_.push_back(p);
    });
    int h = faces_[f].edge;
    do {
      const int next = edges_[h].next;
      free_edge(h);
      h = next;
    } while (h != faces_[f].edge);
    free_face(f);
  }

  // Merge faces (Gregorius 2014, with a planarity test instead of his centroid test, which
  // let corners stray several tolerances off the merged plane). A merge or a removed corner
  // changes a plane, so repeat until nothing merges.
  for (bool merged = true; merged;) {
    merged = false;
    for (size_t i = 0; i < work_.size(); ++i) {
      const int f = work_[i];
      if (!faces_[f].alive) continue;
      while (merge_step(f)) merged = true;
    }
  }

  // Faces that changed hand their outside points back; all orphans go to the changed faces.
  // A point above a removed face that lies outside the new hull is above one of the cone faces
  // (Barber et al. 1996), and every cone face lives on in a changed face.
  std::vector<int>& changed = visible_;  // reuse as scratch
  changed.clear();
  for (int f : work_) {
    faces_[f].queued = false;
    if (!faces_[f].alive) continue;
    changed.push_back(f);
    for_each_outside(f, [&](int p) { orphans_.push_back(p); });
    clear_outside(f);
    faces_[f].furthest = -1;
    furthest_[f] = 0.0;
  }
  for (int p : orphans_) assign(p, changed);
}

// The lowest and highest of the corners of faces f and g along `direction`, stopping early
// (with what it has) once stop(lo, hi) holds.
template <class Stop>
std::pair<double, double> QuickHull::union_heights(int f, int g, const DVec3& direction, Stop&& stop) const {
  double lo = HUGE_VAL;
  double hi = -HUGE_VAL;
  for (int face : {f, g}) {
    int h = faces_[face].edge;
    do {
      const double d = glm::dot(direction, pts_[edges_[h].origin]);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
      if (stop(lo, hi)) return {lo, hi};
      h = edges_[h].next;
    } while (h != faces_[face].edge);
  }
  return {lo, hi};
}

// Corners of faces f and g spread along the normal of their union (Newell's area vector of
// the union is the sum of theirs: the shared edges cancel).
double QuickHull::union_spread(int f, int g) const {
  const DVec3 sum = faces_[f].area_vector + faces_[g].area_vector;
  const double len = glm::length(sum);
  if (!(len > 0.0)) return HUGE_VAL;
  const auto [lo, hi] = union_heights(f, g, sum / len, [](double, double) { return false; });
  return hi - lo;
}

// Whether union_spread(f, g) <= limit, without its square root and division: along the
// unnormalised area vector S every height is |S| times the unit one, so the spread is compared
// squared against limit^2 |S|^2; stops at the first corner past it. (The merge test's most
// frequent question: union_spread was a fifth of a build on Jolt's clouds, a third of that its
// normalisation.)
bool QuickHull::union_within(int f, int g, double limit) const {
  const DVec3 sum = faces_[f].area_vector + faces_[g].area_vector;
  const double length2 = glm::dot(sum, sum);
  if (!(length2 > 0.0)) return false;
  const double bound = limit * limit * length2;
  const auto past = [bound](double lo, double hi) { return (hi - lo) * (hi - lo) > bound; };
  const auto [lo, hi] = union_heights(f, g, sum, past);
  return !past(lo, hi);
}

SharedRun QuickHull::shared_run(int f, int h) const {
  const int g = edges_[edges_[h].twin].face;
  SharedRun run{h, h, -1, -1, -1, -1};
  while (edges_[edges_[edges_[run.first].prev].twin].face == g && edges_[run.first].prev != h) {
    run.first = edges_[run.first].prev;
  }
  while (edges_[edges_[edges_[run.last].next].twin].face == g &&
         edges_[run.last].next != run.first) {
    run.last = edges_[run.last].next;
  }
  (void)f;
  run.p = edges_[run.first].prev;
  run.n = edges_[run.last].next;
  run.m = edges_[edges_[run.first].twin].next;
  run.q = edges_[edges_[run.last].twin].prev;
  return run;
}

// Whether all edges f shares with the face across h form one run. Two separate runs would
// enclose other faces, and merging across one would leave edges with f on both sides; such
// pairs are never merged (not seen on any test cloud).
bool QuickHull::shares_one_run(int f, int h) const {
  const int g = edges_[edges_[h].twin].face;
  const SharedRun run = shared_run(f, h);
  int in_run = 1;
  for (int e = run.first; e != run.last; e = edges_[e].next) ++in_run;
  int shared = 0;
  int e = faces_[f].edge;
  do {
    if (edges_[edges_[e].twin].face == g) ++shared;
    e = edges_[e].next;
  } while (e != faces_[f].edge);
  return shared == in_run;
}

// How far corner b of the polygon path a -> b -> c lies on the outer side of the chord a -> c,
// in the plane with the given normal: positive where the corner is convex.
double QuickHull::corner_turn(int a, int b, int c, const DVec3& normal) const {
  const DVec3 chord = pts_[c] - pts_[a];
  const double len = glm::length(chord);
  if (!(len > 0.0)) return 0.0;
  return glm::dot(pts_[b] - pts_[a], glm::cross(chord, normal)) / len;
}

// Faces f and g (across f's half-edge h) become one when their union is planar within
// kCoplanarFraction of the tolerance (coplanar points, slivers along an edge) and stays a convex
// polygon, or when their edge is concave (the hull must stay convex), judged first by the plane
// of the larger face: a sliver's own plane is unreliable.
bool QuickHull::should_merge(int f, int h) const {
  const int g = edges_[edges_[h].twin].face;
  const double limit = kCoplanarFraction * tol_;
  if (union_within(f, g, limit)) {
    if (!shares_one_run(f, h)) return false;
    // The union's corners at the ends of the shared run: p -> m at its start, q -> n at its end.
    // A reflex one is fine when only one other face touches that vertex: it then lies on an
    // edge (or inside a face being merged piece by piece) and fix_degree_two_vertices removes it.
    const SharedRun run = shared_run(f, h);
    const DVec3 normal = glm::normalize(faces_[f].area_vector + faces_[g].area_vector);
    auto face_across = [&](int e) { return edges_[edges_[e].twin].face; };
    const bool start_ok =
        face_across(run.p) == face_across(run.m) ||
        corner_turn(edges_[run.p].origin, edges_[run.m].origin, end_of(run.m), normal) >= -limit;
    const bool end_ok =
        face_across(run.q) == face_across(run.n) ||
        corner_turn(edges_[run.q].origin, edges_[run.n].origin, end_of(run.n), normal) >= -limit;
    if (start_ok && end_ok) return true;
  }
  const bool f_larger = faces_[f].area >= faces_[g].area;
  const int big = f_larger ? f : g;
  const int small = f_larger ? g : f;
  const bool concave = distance(big, faces_[small].centroid) > 0.0 ||
                       distance(small, faces_[big].centroid) > 0.0;
  return concave && shares_one_run(f, h);
}

// A face no wider than the tolerance across one of its sides (a sliver). A convex polygon lies
// in a strip as wide as its width across any side and no longer than its diameter, so its area
// is at most that width times the diameter: a face whose area passes the tolerance times a
// bound on its diameter (its corners' box diagonal), by kThinTestMargin, is wider than the
// tolerance across every side, and most faces are settled so, in one pass over their corners,
// instead of the loop below (a square root per side and corner: a tenth of the build on Jolt's
// clouds, bench_convex_hull).
bool QuickHull::is_thin(int f) const {
  DVec3 lo{HUGE_VAL};
  DVec3 hi{-HUGE_VAL};
  int h = faces_[f].edge;
  do {
    lo = glm::min(lo, pts_[edges_[h].origin]);
    hi = glm::max(hi, pts_[edges_[h].origin]);
    h = edges_[h].next;
  } while (h != faces_[f].edge);
  if (faces_[f].area > kThinTestMargin * tol_ * glm::length(hi - lo)) return false;
  do {
    const DVec3 a = pts_[edges_[h].origin];
    const DVec3 side = pts_[end_of(h)] - a;
    const double len = glm::length(side);
    double width = 0.0;
    int k = faces_[f].edge;
    do {
      width = std::max(width, glm::length(glm::cross(side, pts_[edges_[k].origin] - a)));
      k = edges_[k].next;
    } while (k != faces_[f].edge);
    if (width <= tol_ * len) return true;
    h = edges_[h].next;
  } while (h != faces_[f].edge);
  return false;
}

// Once a face merges with none of its neighbours, it stays so until the hull changes
// (changes_ moves): the repeated passes of add_point's merge loop skip it, and its neighbours
// skip the question of merging with it. should_merge answers a pair the same from either side:
// its planarity and concavity tests are symmetric in the two faces, and its corner tests look
// at the same two corners from the other end of the chord (equal but for rounding, at a turn
// within an ulp of the limit). On Jolt's clouds that leaves out about a third of the merge
// tests, every hull bit for bit the same.
bool QuickHull::merge_step(int f) {
  if (faces_[f].clean_at == changes_) return false;
  if (is_thin(f)) {
    // Into the neighbour it is most nearly coplanar with.
    int best = -1;
    double best_spread = HUGE_VAL;
    int h = faces_[f].edge;
    do {
      const double spread = union_spread(f, edges_[edges_[h].twin].face);
      if (spread < best_spread && shares_one_run(f, h)) {
        best_spread = spread;
        best = h;
      }
      h = edges_[h].next;
    } while (h != faces_[f].edge);
    if (best >= 0) {
      merge(f, best);
      return true;
    }
  }
  int h = faces_[f].edge;
  do {
    if (faces_[edges_[edges_[h].twin].face].clean_at != changes_ && should_merge(f, h)) {
      merge(f, h);
      return true;
    }
    h = edges_[h].next;
  } while (h != faces_[f].edge);
  faces_[f].clean_at = changes_;
  return false;
}

// Face f absorbs its neighbour across half-edge h. The whole run of edges the two share goes
// (its inner vertices touch only these two faces), so the union is one simple polygon.
void QuickHull::merge(int f, int h) {
  const int g = edges_[edges_[h].twin].face;
  if (g == f || g < 0) throw FoldedFlat{};
  const SharedRun run = shared_run(f, h);
  const int first = run.first;
  const int last = run.last;
  const int p = run.p;
  const int n = run.n;
  const int m = run.m;
  const int q = run.q;
  const int t_last = edges_[last].twin;
  int run_length = 1;
  for (int e = first; e != last; e = edges_[e].next) ++run_length;
  if (edge_count(f) + edge_count(g) - 2 * run_length < 3) throw FoldedFlat{};

  // g's remaining edges join f.
  for (int e = m; e != t_last; e = edges_[e].next) edges_[e].face = f;
  // Free the shared run on both sides.
  for (int e = first;;) {
    const int next = edges_[e].next;
    free_edge(edges_[e].twin);
    free_edge(e);
    if (e == last) break;
    e = next;
  }
  edges_[p].next = m;
  edges_[m].prev = p;
  edges_[q].next = n;
  edges_[n].prev = q;
  faces_[f].edge = p;

  for_each_outside(g, [&](int pt) { orphans_.push_back(pt); });
  clear_outside(g);
  faces_[g].queued = false;  // stays in work_ but is skipped as dead
  free_face(g);

  fix_degree_two_vertices(f);
  compute_plane(f);
  enqueue(f);
}

// After a merge, a corner of f may touch only f and one other face N (two consecutive edges of
// f border N): it lies on their common edge and is no vertex. If N or f is a triangle, N is
// absorbed across both shared edges (a triangle would otherwise lose a side); else the corner
// is removed from both faces.
void QuickHull::fix_degree_two_vertices(int f) {
  bool changed = true;
  while (changed) {
    changed = false;
    int h = faces_[f].edge;
    do {
      const int n = edges_[h].next;
      const int other = edges_[edges_[h].twin].face;
      if (other == edges_[edges_[n].twin].face) {
        if (edge_count(other) == 3 || edge_count(f) == 3) {
          merge(f, h);  // a triangle would lose a side: absorb across both shared edges
          return;
        }
        const int th = edges_[h].twin;  // v -> u in other
        const int tn = edges_[n].twin;  // w -> v in other
        // In f: h becomes u -> w.
        edges_[h].next = edges_[n].next;
        edges_[edges_[n].next].prev = h;
        // In other: tn becomes w -> u.
        edges_[tn].next = edges_[th].next;
        edges_[edges_[th].next].prev = tn;
        edges_[h].twin = tn;
        edges_[tn].twin = h;
        if (faces_[f].edge == n) faces_[f].edge = h;
        if (faces_[other].edge == th) faces_[other].edge = tn;
        free_edge(n);
        free_edge(th);
        compute_plane(other);
        enqueue(other);
        changed = true;
        break;
      }
      h = n;
    } while (h != faces_[f].edge);
  }
}

void QuickHull::extract(bool contain_inputs, ConvexHull& hull) {
  const std::span<const Vec3> input = input_;
  // Vertices in input order. (The arrays are sized before they are filled: a hull of 17
  // vertices grew each of them through five allocations.)
  std::vector<int>& index_of = index_of_;
  index_of.assign(pts_.size(), -1);  // -2: a hull vertex, numbered below
  std::size_t corners = 0;                     // half-edges: every face's corners
  for (const HalfEdge& e : edges_) {
    if (e.face >= 0) {
      index_of[e.origin] = -2;
      ++corners;
    }
  }
  std::vector<int>& point_of = point_of_;
  point_of.clear();
  for (size_t i = 0; i < pts_.size(); ++i) {
    if (index_of[i] == -2) {
      index_of[i] = static_cast<int>(point_of.size());
      point_of.push_back(static_cast<int>(i));
    }
  }
  hull.vertices.clear();
  hull.vertices.reserve(point_of.size());
  for (int p : point_of) hull.vertices.push_back(input[p]);
  const int vcount = static_cast<int>(point_of.size());
  const int blocks = (vcount + 3) / 4;
  hull.vertex_blocks.assign(static_cast<size_t>(blocks) * 12, 0.0f);
  for (int b = 0; b < blocks; ++b) {
    for (int lane = 0; lane < 4; ++lane) {
      const int i = 4 * b + lane;
      const Vec3 v = hull.vertices[i < vcount ? i : 0];  // padding: ties go to vertex 0
      for (int k = 0; k < 3; ++k) hull.vertex_blocks[12 * b + 4 * k + lane] = v[k];
    }
  }

  // Faces, their corners, and edges (each undirected edge once, v0 < v1).
  std::vector<int>& face_of = face_of_;
  face_of.assign(faces_.size(), -1);
  std::vector<int>& live = live_;
  live.clear();
  for (int f = 0; f < static_cast<int>(faces_.size()); ++f) {
    if (faces_[f].alive) {
      face_of[f] = static_cast<int>(live.size());
      live.push_back(f);
    }
  }
  std::vector<int>& edge_of = edge_of_;
  edge_of.assign(edges_.size(), -1);
  hull.faces.clear();
  hull.faces.reserve(live.size());
  hull.face_vertices.clear();
  hull.face_vertices.reserve(corners);
  hull.face_edges.clear();
  hull.face_edges.reserve(corners);
  hull.edges.clear();
  hull.edges.reserve(corners / 2);
  for (int f : live) {
    HullFace out{};
    out.first = static_cast<std::uint16_t>(hull.face_vertices.size());
    int h = faces_[f].edge;
    int count = 0;
    do {
      hull.face_vertices.push_back(static_cast<HullVertexIndex>(index_of[edges_[h].origin]));
      if (edge_of[h] < 0) {
        const int t = edges_[h].twin;
        const int a = index_of[edges_[h].origin];
        const int b = index_of[edges_[t].origin];
        HullEdge e{};
        e.v0 = static_cast<HullVertexIndex>(std::min(a, b));
        e.v1 = static_cast<HullVertexIndex>(std::max(a, b));
        const int left = a < b ? f : edges_[t].face;
        const int right = a < b ? edges_[t].face : f;
        e.face0 = static_cast<std::uint16_t>(face_of[left]);
        e.face1 = static_cast<std::uint16_t>(face_of[right]);
        edge_of[h] = edge_of[t] = static_cast<int>(hull.edges.size());
        hull.edges.push_back(e);
      }
      hull.face_edges.push_back(static_cast<std::uint16_t>(edge_of[h]));
      ++count;
      h = edges_[h].next;
    } while (h != faces_[f].edge);
    out.count = static_cast<std::uint16_t>(count);
    // The normal in float; the offset supports every vertex, evaluated in double on the input
    // coordinates with that float normal (the planes the last sweep checked every point
    // against).
    out.normal = faces_[f].stored_normal;
    const DVec3 n(out.normal);
    double offset = -HUGE_VAL;
    if (swept_) {
      offset = swept_offset_[f];
    } else {
      for (int p : point_of) offset = std::max(offset, glm::dot(n, DVec3(input[p])));
    }
    if (contain_inputs) {
      for (const Vec3& p : input) offset = std::max(offset, glm::dot(n, DVec3(p)) - tol_);
    }
    // Rounded up, so the float plane still has every vertex (and point) behind it.
    out.offset = static_cast<float>(offset);
    if (static_cast<double>(out.offset) < offset) {
      out.offset = std::nextafter(out.offset, HUGE_VALF);
    }
    hull.faces.push_back(out);
  }
  const int face_count = static_cast<int>(hull.faces.size());
  const int face_blocks = (face_count + 3) / 4;
  hull.face_blocks.assign(static_cast<size_t>(face_blocks) * 16, 0.0f);
  for (int b = 0; b < face_blocks; ++b) {
    for (int lane = 0; lane < 4; ++lane) {
      const int f = 4 * b + lane;
      const HullFace& face = hull.faces[f < face_count ? f : 0];  // padding: ties go to face 0
      for (int k = 0; k < 3; ++k) hull.face_blocks[16 * b + 4 * k + lane] = face.normal[k];
      hull.face_blocks[16 * b + 12 + lane] = face.offset;
    }
  }

  // Vertex adjacency (CSR) from the edges.
  hull.neighbour_offsets.assign(static_cast<size_t>(vcount) + 1, 0);
  for (const HullEdge& e : hull.edges) {
    ++hull.neighbour_offsets[e.v0 + 1];
    ++hull.neighbour_offsets[e.v1 + 1];
  }
  for (int i = 0; i < vcount; ++i) hull.neighbour_offsets[i + 1] += hull.neighbour_offsets[i];
  hull.neighbours.assign(hull.edges.size() * 2, 0);
  std::vector<int>& fill = fill_;
  fill.assign(hull.neighbour_offsets.begin(), hull.neighbour_offsets.end() - 1);
  for (const HullEdge& e : hull.edges) {
    hull.neighbours[fill[e.v0]++] = e.v1;
    hull.neighbours[fill[e.v1]++] = e.v0;
  }

  // Volume and centroid: tetrahedra from an inner point to each face's fan, in the build's
  // shifted frame (double), then back.
  DVec3 inner{0.0};
  for (int p : point_of) inner += pts_[p];
  inner /= static_cast<double>(vcount);
  double volume = 0.0;
  DVec3 moment{0.0};
  for (int f : live) {
    const int h0 = faces_[f].edge;
    const DVec3 a = pts_[edges_[h0].origin] - inner;
    for (int h = edges_[h0].next; edges_[h].next != h0; h = edges_[h].next) {
      const DVec3 b = pts_[edges_[h].origin] - inner;
      const DVec3 c = pts_[edges_[edges_[h].next].origin] - inner;
      const double v = glm::dot(a, glm::cross(b, c)) / 6.0;
      volume += v;
      moment += v * (a + b + c) * 0.25;
    }
  }
  hull.volume = static_cast<float>(volume);
  hull.centroid = Vec3(origin_ + inner + moment / volume);

  Vec3 lo = hull.vertices[0];
  Vec3 hi = lo;
  for (const Vec3& v : hull.vertices) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  hull.bounds = {lo, hi};
}

}  // namespace

ConvexHull make_convex_hull(std::span<const Vec3> points, const HullOptions& options) {
  if (!std::isfinite(options.radius)) throw InvalidInput("convex hull radius: not finite");
  if (options.radius < 0.0f) {
    throw InvalidInput("convex hull radius: negative (" + std::to_string(options.radius) + ")");
  }
  if (options.max_vertices < 4 || options.max_vertices > kMaxHullVertices) {
    throw InvalidInput("convex hull max_vertices: " + std::to_string(options.max_vertices) +
                       " is outside [4, " + std::to_string(kMaxHullVertices) + "]");
  }
  for (size_t i = 0; i < points.size(); ++i) {
    if (!is_finite(points[i])) {
      throw InvalidInput("convex hull point " + std::to_string(i) + ": not finite");
    }
  }
  if (points.size() < 4) {
    throw InvalidInput("convex hull points: needs at least 4, got " +
                       std::to_string(points.size()));
  }

  // Shift to the centre of the bounding box: differences of far-away points stay exact.
  DVec3 lo(points[0]);
  DVec3 hi(points[0]);
  DVec3 max_abs_coord{0.0};
  for (const Vec3& p : points) {
    lo = glm::min(lo, DVec3(p));
    hi = glm::max(hi, DVec3(p));
    max_abs_coord = glm::max(max_abs_coord, glm::abs(DVec3(p)));
  }
  const DVec3 center = 0.5 * (lo + hi);
  const DVec3 size = hi - lo;
  const double extent = std::max({size.x, size.y, size.z});
  const double tolerance =
      std::max(static_cast<double>(kHullRelativeTolerance) * extent,
               static_cast<double>(kHullRoundingFactor) * static_cast<double>(FLT_EPSILON) *
                   (max_abs_coord.x + max_abs_coord.y + max_abs_coord.z));
  thread_local QuickHull builder;
  builder.reset(points, center, tolerance, options.max_vertices);
  struct Trim {  // on every way out, a throw included
    QuickHull& builder;
    ~Trim() { builder.trim(); }
  } trim{builder};
  if (const char* degenerate = builder.build_initial()) {
    throw InvalidInput(std::string("convex hull points: ") + degenerate + " (zero volume)");
  }
  QuickHull::Outcome outcome{};
  try {
    outcome = builder.run(options.max_vertices);
  } catch (const FoldedFlat&) {
    throw InvalidInput(
        "convex hull points: too thin for the tolerance (merging faces within it folded the "
        "hull flat; zero volume)");
  }
  ConvexHull hull;
  builder.extract(outcome == QuickHull::Outcome::unverified, hull);
  hull.radius = options.radius;
  hull.tolerance = static_cast<float>(tolerance);
  return hull;
}

int ConvexHull::climb_support(Vec3 direction, int start) const noexcept {
  int current = start;
  float current_dot = dot(vertices[current], direction);
  for (;;) {
    int best = current;
    float best_dot = current_dot;
    for (int k = neighbour_offsets[current]; k < neighbour_offsets[current + 1]; ++k) {
      const int j = neighbours[k];
      const float d = dot(vertices[j], direction);
      if (d > best_dot) {
        best_dot = d;
        best = j;
      }
    }
    if (best == current) return current;
    current = best;
    current_dot = best_dot;
  }
}

Aabb3 compute_aabb(const ConvexHull& hull, const Transform3& xf) noexcept {
  const Frame3 frame = Frame3::from(xf);
  Vec3 lo = transform_point(frame, hull.vertices[0]);
  Vec3 hi = lo;
  for (const Vec3& v : hull.vertices) {
    const Vec3 w = transform_point(frame, v);
    lo = glm::min(lo, w);
    hi = glm::max(hi, w);
  }
  const Vec3 r{hull.radius};
  return {lo - r, hi + r};
}

}  // namespace collide
