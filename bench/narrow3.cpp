// The 3D narrow phase on real convex hulls: collide vs Jolt, libccd, FCL 0.7 and Bullet 3, side
// by side in one run on the same inputs.
//
// Workload (tests/support/hull_pairs.hpp): 1024 clouds of Jolt's convex_hulls.bin (Horizon Zero
// Dawn rocks and props, ../shared/data/SOURCES.md), each centred on its hull's centroid and
// scaled so that its bounding box's longest side is 1. Three sets of 1024 pairs of them, turned
// by random rotations, A anywhere within 10 of the origin, and B placed along a random
// direction at the exact touching offset (in double) plus a gap of 0.01-0.5 (separated), minus
// a penetration of 0.01-0.25 (overlapping), or plus a gap with A moving 0.01-0.6 towards B
// (approaching; about half of them meet). Every library gets the same polytope: collide's hull
// vertices (copies of cloud points) are the points of Jolt's ConvexHullShape (convex radius 0,
// hull tolerance = collide's), of Bullet's btConvexHullShape (margin 0), of FCL's Convex (with
// collide's faces) and of the libccd support callbacks.
//
// Benchmarks, each iteration one batch of 1024 queries, named BM_<query>/<set>/<library>:
//  - Overlap (separated, overlapping): collide `overlap` (boolean GJK); Jolt GJKClosestPoint::
//    Intersects; libccd ccdGJKIntersect; FCL collide (no contact); Bullet has no boolean GJK:
//    btGjkEpaSolver2::Distance (full GJK).
//  - Distance with closest points (separated): collide `distance`; Jolt GetClosestPoints; FCL
//    distance with nearest points (libccd and its own "indep" GJK); Bullet btGjkEpaSolver2::
//    Distance. libccd has no distance query of its own.
//  - Depth (overlapping): collide `penetration` (GJK then EPA, narrow/epa.hpp) and, beside it,
//    `contact`'s SAT depth; Jolt EPAPenetrationDepth (GJK step, then EPA); libccd
//    ccdGJKPenetration (EPA) and ccdMPRPenetration; FCL collide with contact (libccd); Bullet
//    btGjkEpaSolver2::Penetration.
//  - Contact (overlapping): the full manifold. collide `contact` (margin 0.02) vs Jolt
//    CollisionDispatch::sCollideShapeVsShape with faces and max separation 0.02, then
//    ManifoldBetweenTwoFaces and PruneContactPoints as its PhysicsSystem does (0.02 is Jolt's
//    PhysicsSettings::mSpeculativeContactDistance); Bullet's SAT path
//    (btPolyhedralContactClipping::findSeparatingAxis + clipHullAgainstHull, no reduction).
//  - ShapeCast (approaching): collide `shape_cast` vs Jolt CollisionDispatch::
//    sCastShapeVsShapeWorldSpace and Bullet btGjkConvexCast (and btContinuousConvexCollision,
//    what btCollisionWorld::convexSweepTest runs). libccd and FCL have no linear shape cast on
//    convex shapes.
// Accuracy: every benchmark checks its library's answers on its 1024 pairs once against the
// exact reference of hull_pairs.hpp (double) and reports them as counters beside the time
// (errors in units of the hull size; Google Benchmark prints them with SI prefixes: m = 1e-3,
// u = 1e-6, n = 1e-9):
//  - wrong:      wrong yes/no answers (overlap; distance reporting contact; depth and contact
//                finding none); for casts `misses` (a real contact not found) and `false_hits`
//                (a hit where the shapes pass more than 1e-4 apart; closer passes are grazes and
//                count as right either way);
//  - max_err, mean_err: |distance, depth or first-touch distance along the motion - exact|;
//  - points_err: closest points: the larger of their distances from their shapes' surfaces
//                and of | |pa - pb| - exact distance | (the worst pair);
//  - normal_err: depth and contact: how much further than the true depth B must move along the
//                reported normal to separate (exact for any normal; 0 for the best axis);
//  - points:     contact: mean manifold points.
// Pairs answered wrongly are listed on stderr. The instruction set of each side is in the
// context block.
//
// Run: ./build/release/bench/bench_narrow3 --benchmark_enable_random_interleaving=true \
//        --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// bench_narrow3_avx2 (built on request) is the same with collide's library compiled -mavx2 -mfma
// ... (Jolt's set).

#include <collide/ccd/shape_cast.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/epa.hpp>
#include <collide/narrow/overlap.hpp>

#include "instruction_set.hpp"
#include "support/brute_query3.hpp"
#include "support/hull_pairs.hpp"
#include "support/jolt/jolt_convert.hpp"
#include "support/jolt/jolt_queries.hpp"

#include <benchmark/benchmark.h>
#include <btBulletCollisionCommon.h>
#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>
#include <BulletCollision/NarrowPhaseCollision/btContinuousConvexCollision.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkConvexCast.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>
#include <BulletCollision/NarrowPhaseCollision/btPolyhedralContactClipping.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>
#include <ccd/ccd.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using namespace collide;
using test::jolt_pose;  // support/jolt/jolt_convert.hpp
using collide::test::DVec3;

constexpr int kPairs = 1024;
constexpr int kHulls = 1024;
constexpr float kHullSize = 1.0f;
/// Speculative contact distance of the manifold benchmark: Jolt's
/// PhysicsSettings::mSpeculativeContactDistance, used as collide's margin too.
constexpr float kContactMargin = 0.02f;

// ---- the peers' shapes and placements -----------------------------------------------------------

/// libccd's view of a placed hull: support and centre callbacks in double.
struct CcdBody {
  const std::vector<double>* points = nullptr;  ///< local xyz
  double r[9] = {};                             ///< world = r * local + p, row-major
  double p[3] = {};
  double center[3] = {};
};

void ccd_support(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const CcdBody& b = *static_cast<const CcdBody*>(obj);
  const double* d = dir->v;
  const double lx = b.r[0] * d[0] + b.r[3] * d[1] + b.r[6] * d[2];
  const double ly = b.r[1] * d[0] + b.r[4] * d[1] + b.r[7] * d[2];
  const double lz = b.r[2] * d[0] + b.r[5] * d[1] + b.r[8] * d[2];
  const std::vector<double>& pts = *b.points;
  size_t best = 0;
  double best_dot = -1e300;
  for (size_t i = 0; i < pts.size(); i += 3) {
    const double v = lx * pts[i] + ly * pts[i + 1] + lz * pts[i + 2];
    if (v > best_dot) {
      best_dot = v;
      best = i;
    }
  }
  for (int k = 0; k < 3; ++k) {
    out->v[k] = b.r[3 * k] * pts[best] + b.r[3 * k + 1] * pts[best + 1] +
                b.r[3 * k + 2] * pts[best + 2] + b.p[k];
  }
}

void ccd_center(const void* obj, ccd_vec3_t* out) {
  const CcdBody& b = *static_cast<const CcdBody*>(obj);
  for (int k = 0; k < 3; ++k) out->v[k] = b.center[k];
}

/// Collects Bullet's contact points (btDiscreteCollisionDetectorInterface::Result).
struct BulletContacts : btDiscreteCollisionDetectorInterface::Result {
  int count = 0;
  float depth = -1e30f;  ///< deepest penetration (Bullet reports -depth as the distance)
  btVector3 normal{0, 0, 0};
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3& normal_on_b, const btVector3&, btScalar distance) override {
    ++count;
    if (-distance > depth) {
      depth = -distance;
      normal = -normal_on_b;
    }
  }
};

/// One hull in every library.
struct Hull {
  ConvexHull collide;
  jolt_queries::HullPtr jolt;
  std::unique_ptr<btConvexHullShape> bullet;
  std::shared_ptr<fcl::Convexd> fcl;
  std::vector<double> ccd_points;
};

/// A pair placed in every library.
struct Pair {
  const Hull* a = nullptr;
  const Hull* b = nullptr;
  Transform3 xa, xb;
  Vec3 va{0.0f};
  jolt_queries::Body ja, jb;
  btTransform ta, tb;
  fcl::Transform3d fa, fb;
  CcdBody ca, cb;
  // The exact reference (double).
  collide::test::BruteCore core_a, core_b;  ///< separated pairs: for the closest points
  bool overlapping = false;
  double distance = 0.0;  ///< separated pairs
  double depth = 0.0;     ///< overlapping pairs
  double touch = -1.0;    ///< approaching pairs: first touch fraction, < 0 for a miss
  collide::test::MinkowskiReference k;
};

btTransform bullet_transform(const Transform3& xf) {
  return btTransform(btQuaternion(xf.q.x, xf.q.y, xf.q.z, xf.q.w),
                     btVector3(xf.p.x, xf.p.y, xf.p.z));
}

fcl::Transform3d fcl_transform(const Transform3& xf) {
  const glm::dmat3 m = glm::mat3_cast(glm::dquat(xf.q.w, xf.q.x, xf.q.y, xf.q.z));
  fcl::Transform3d t = fcl::Transform3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) t.linear()(r, c) = m[c][r];
  }
  t.translation() = fcl::Vector3d(xf.p.x, xf.p.y, xf.p.z);
  return t;
}

CcdBody ccd_body(const Hull& h, const Transform3& xf) {
  CcdBody b;
  b.points = &h.ccd_points;
  const glm::dmat3 m = glm::mat3_cast(glm::dquat(xf.q.w, xf.q.x, xf.q.y, xf.q.z));
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) b.r[3 * r + c] = m[c][r];
    b.p[r] = xf.p[r];
  }
  const DVec3 c = collide::test::to_world(xf, h.collide.centroid);
  for (int k = 0; k < 3; ++k) b.center[k] = c[k];
  return b;
}

Hull make_hull(ConvexHull hull) {
  Hull h;
  h.collide = std::move(hull);
  const ConvexHull& c = h.collide;
  std::vector<jolt_queries::Vec> jpts;
  for (const Vec3& v : c.vertices) jpts.push_back({v.x, v.y, v.z});
  h.jolt = jolt_queries::make_hull(jpts, c.tolerance);
  h.bullet = std::make_unique<btConvexHullShape>();
  for (const Vec3& v : c.vertices) h.bullet->addPoint(btVector3(v.x, v.y, v.z), false);
  h.bullet->recalcLocalAabb();
  h.bullet->setMargin(0.0f);
  h.bullet->initializePolyhedralFeatures();
  auto verts = std::make_shared<std::vector<fcl::Vector3d>>();
  for (const Vec3& v : c.vertices) verts->emplace_back(v.x, v.y, v.z);
  auto faces = std::make_shared<std::vector<int>>();
  for (const HullFace& f : c.faces) {
    faces->push_back(f.count);
    for (int k = 0; k < f.count; ++k) faces->push_back(c.face_vertices[f.first + k]);
  }
  h.fcl = std::make_shared<fcl::Convexd>(verts, static_cast<int>(c.faces.size()), faces);
  for (const Vec3& v : c.vertices) {
    h.ccd_points.insert(h.ccd_points.end(), {double(v.x), double(v.y), double(v.z)});
  }
  return h;
}

// ---- the workload -------------------------------------------------------------------------------

struct Workload {
  std::vector<Hull> hulls;
  std::vector<Pair> separated, overlapping, approaching;
  int jolt_vertex_mismatch = 0;  ///< hulls where Jolt kept another number of vertices
};

std::vector<Pair> place(const Workload& w, collide::test::Placement placement, unsigned seed) {
  std::vector<ConvexHull> plain;  // make_hull_pairs reads collide's hulls
  plain.reserve(w.hulls.size());
  for (const Hull& h : w.hulls) plain.push_back(h.collide);
  std::vector<Pair> out;
  for (const collide::test::HullPair& hp :
       collide::test::make_hull_pairs(plain, kPairs, placement, seed)) {
    Pair p;
    p.a = &w.hulls[hp.a];
    p.b = &w.hulls[hp.b];
    p.xa = hp.xa;
    p.xb = hp.xb;
    p.va = hp.va;
    p.ja = jolt_queries::place(*p.a->jolt, jolt_pose(p.xa));
    p.jb = jolt_queries::place(*p.b->jolt, jolt_pose(p.xb));
    p.ta = bullet_transform(p.xa);
    p.tb = bullet_transform(p.xb);
    p.fa = fcl_transform(p.xa);
    p.fb = fcl_transform(p.xb);
    p.ca = ccd_body(*p.a, p.xa);
    p.cb = ccd_body(*p.b, p.xb);
    p.k = collide::test::minkowski_reference(p.a->collide, p.xa, p.b->collide, p.xb);
    p.overlapping = p.k.overlapping();
    if (placement == collide::test::Placement::separated) {
      p.core_a = collide::test::brute_core(p.a->collide, p.xa);
      p.core_b = collide::test::brute_core(p.b->collide, p.xb);
      p.distance = collide::test::brute_core_distance(p.core_a, p.core_b);
    }
    if (placement == collide::test::Placement::overlapping) p.depth = p.k.depth();
    if (placement == collide::test::Placement::approaching) p.touch = p.k.first_touch(DVec3(p.va));
    out.push_back(std::move(p));
  }
  return out;
}

const Workload& workload() {
  static const Workload w = [] {
    jolt_queries::init();
    Workload w;
    std::vector<ConvexHull> hulls = collide::test::scaled_jolt_hulls(kHullSize, kHulls);
    for (ConvexHull& h : hulls) {
      Hull hull = make_hull(std::move(h));
      if (!hull.jolt) continue;  // never seen: Jolt builds every cloud
      if (jolt_queries::vertex_count(*hull.jolt) != hull.collide.vertex_count()) {
        ++w.jolt_vertex_mismatch;
      }
      w.hulls.push_back(std::move(hull));
    }
    w.separated = place(w, collide::test::Placement::separated, 1);
    w.overlapping = place(w, collide::test::Placement::overlapping, 2);
    w.approaching = place(w, collide::test::Placement::approaching, 3);
    return w;
  }();
  return w;
}

// ---- the queries, one pair each -----------------------------------------------------------------

/// A contact normal (A to B) and depth, or a penetration depth result.
struct Depth {
  bool hit = false;
  double depth = 0.0;
  DVec3 normal{0.0};
  int points = 0;
};

DVec3 dvec(Vec3 v) { return DVec3(v); }
DVec3 dvec(const btVector3& v) { return DVec3(v.x(), v.y(), v.z()); }
DVec3 dvec(const jolt_queries::Vec& v) { return DVec3(v.x, v.y, v.z); }

bool overlap_collide(const Pair& p) { return overlap(p.a->collide, p.xa, p.b->collide, p.xb); }
bool overlap_jolt(const Pair& p) { return jolt_queries::overlap(p.ja, p.jb); }

ccd_t make_ccd() {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = ccd_support;
  ccd.support2 = ccd_support;
  ccd.center1 = ccd_center;
  ccd.center2 = ccd_center;
  ccd.max_iterations = 500;  // FCL's choice; the default is unbounded
  return ccd;
}
const ccd_t kCcd = make_ccd();

bool overlap_ccd(const Pair& p) { return ccdGJKIntersect(&p.ca, &p.cb, &kCcd) != 0; }
bool overlap_fcl(const Pair& p) {
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl::collide(p.a->fcl.get(), p.fa, p.b->fcl.get(), p.fb, request, result);
  return result.isCollision();
}
bool overlap_bullet(const Pair& p) {
  btGjkEpaSolver2::sResults r;
  return !btGjkEpaSolver2::Distance(p.a->bullet.get(), p.ta, p.b->bullet.get(), p.tb,
                                    p.tb.getOrigin() - p.ta.getOrigin(), r);
}

/// A distance and the closest points on A and B (world space).
struct Closest {
  double distance = 0.0;
  DVec3 point_a{0.0}, point_b{0.0};
};

Closest distance_collide(const Pair& p) {
  const DistanceResult3 r = distance(p.a->collide, p.xa, p.b->collide, p.xb);
  return {r.distance, dvec(r.point_a), dvec(r.point_b)};
}
Closest distance_jolt(const Pair& p) {
  const jolt_queries::DistanceOut r = jolt_queries::distance(p.ja, p.jb);
  return {r.distance, dvec(r.point_a), dvec(r.point_b)};
}
Closest distance_fcl(const Pair& p, fcl::GJKSolverType solver) {
  fcl::DistanceRequestd request(true);
  request.gjk_solver_type = solver;
  fcl::DistanceResultd result;
  const double d = fcl::distance(p.a->fcl.get(), p.fa, p.b->fcl.get(), p.fb, request, result);
  const fcl::Vector3d& a = result.nearest_points[0];
  const fcl::Vector3d& b = result.nearest_points[1];
  return {d, DVec3(a.x(), a.y(), a.z()), DVec3(b.x(), b.y(), b.z())};
}
Closest distance_fcl_ccd(const Pair& p) { return distance_fcl(p, fcl::GST_LIBCCD); }
Closest distance_fcl_indep(const Pair& p) { return distance_fcl(p, fcl::GST_INDEP); }
Closest distance_bullet(const Pair& p) {
  btGjkEpaSolver2::sResults r;
  if (!btGjkEpaSolver2::Distance(p.a->bullet.get(), p.ta, p.b->bullet.get(), p.tb,
                                 p.tb.getOrigin() - p.ta.getOrigin(), r)) {
    return {};
  }
  return {r.distance, dvec(r.witnesses[0]), dvec(r.witnesses[1])};
}

Depth depth_collide_epa(const Pair& p) {
  const PenetrationResult3 r = penetration(p.a->collide, p.xa, p.b->collide, p.xb);
  const bool hit = r.status == QueryStatus::overlapped;
  return {hit, r.depth, dvec(r.normal), hit ? 1 : 0};
}
Depth depth_collide_contact(const Pair& p) {
  const Manifold3 m = contact(p.a->collide, p.xa, p.b->collide, p.xb);
  return {m.count > 0, m.max_depth(), dvec(m.normal), m.count};
}
Depth depth_jolt(const Pair& p) {
  const jolt_queries::DepthOut d = jolt_queries::penetration(p.ja, p.jb);
  return {d.hit, d.depth, dvec(d.normal), d.hit ? 1 : 0};
}
Depth depth_ccd_gjk(const Pair& p) {
  ccd_real_t depth = 0;
  ccd_vec3_t dir, pos;
  if (ccdGJKPenetration(&p.ca, &p.cb, &kCcd, &depth, &dir, &pos) != 0) return {};
  return {true, depth, DVec3(dir.v[0], dir.v[1], dir.v[2]), 1};
}
Depth depth_ccd_mpr(const Pair& p) {
  ccd_real_t depth = 0;
  ccd_vec3_t dir, pos;
  if (ccdMPRPenetration(&p.ca, &p.cb, &kCcd, &depth, &dir, &pos) != 0) return {};
  return {true, depth, DVec3(dir.v[0], dir.v[1], dir.v[2]), 1};
}
Depth depth_fcl(const Pair& p) {
  fcl::CollisionRequestd request(1, true);
  fcl::CollisionResultd result;
  fcl::collide(p.a->fcl.get(), p.fa, p.b->fcl.get(), p.fb, request, result);
  if (!result.isCollision()) return {};
  const fcl::Contactd& c = result.getContact(0);
  return {true, c.penetration_depth, DVec3(c.normal.x(), c.normal.y(), c.normal.z()), 1};
}
Depth depth_bullet(const Pair& p) {
  btGjkEpaSolver2::sResults r;
  if (!btGjkEpaSolver2::Penetration(p.a->bullet.get(), p.ta, p.b->bullet.get(), p.tb,
                                    p.tb.getOrigin() - p.ta.getOrigin(), r)) {
    return {};
  }
  // r.normal is in A's local frame: take the direction from the world witnesses instead.
  return {true, -r.distance, glm::normalize(dvec(r.witnesses[0]) - dvec(r.witnesses[1])), 1};
}

Depth contact_collide(const Pair& p) {
  const Manifold3 m = contact(p.a->collide, p.xa, p.b->collide, p.xb, kContactMargin);
  return {m.count > 0, m.max_depth(), dvec(m.normal), m.count};
}
Depth contact_jolt(const Pair& p) {
  const jolt_queries::ContactOut c = jolt_queries::contact(p.ja, p.jb, kContactMargin);
  return {c.count > 0, c.depth, dvec(c.normal), c.count};
}
Depth contact_bullet(const Pair& p) {
  const btConvexPolyhedron& ha = *p.a->bullet->getConvexPolyhedron();
  const btConvexPolyhedron& hb = *p.b->bullet->getConvexPolyhedron();
  BulletContacts out;
  btVector3 axis;
  if (!btPolyhedralContactClipping::findSeparatingAxis(ha, hb, p.ta, p.tb, axis, out)) return {};
  btVertexArray verts1, verts2;
  btPolyhedralContactClipping::clipHullAgainstHull(axis, ha, hb, p.ta, p.tb, -1e30f,
                                                   kContactMargin, verts1, verts2, out);
  return {out.count > 0, out.depth, dvec(out.normal), out.count};
}

/// Fraction of first touch, or -1 for a miss.
double cast_collide(const Pair& p) {
  const ShapeCastResult3 r = shape_cast(p.a->collide, p.xa, p.va, p.b->collide, p.xb, Vec3(0.0f));
  return r.hit ? r.fraction : -1.0;
}
double cast_jolt(const Pair& p) {
  const jolt_queries::CastOut r = jolt_queries::cast(p.ja, {p.va.x, p.va.y, p.va.z}, p.jb);
  return r.hit ? r.fraction : -1.0;
}
template <class Cast>
double cast_bullet(const Pair& p) {
  btVoronoiSimplexSolver simplex;
  btGjkEpaPenetrationDepthSolver epa;
  Cast cast = [&] {
    if constexpr (std::is_same_v<Cast, btGjkConvexCast>) {
      return Cast(p.a->bullet.get(), p.b->bullet.get(), &simplex);
    } else {
      return Cast(p.a->bullet.get(), p.b->bullet.get(), &simplex, &epa);
    }
  }();
  btConvexCast::CastResult r;
  btTransform to_a = p.ta;
  to_a.setOrigin(p.ta.getOrigin() + btVector3(p.va.x, p.va.y, p.va.z));
  if (!cast.calcTimeOfImpact(p.ta, to_a, p.tb, p.tb, r)) return -1.0;
  return r.m_fraction;
}
/// What btCollisionWorld::convexSweepTest runs.
double cast_bullet_continuous(const Pair& p) { return cast_bullet<btContinuousConvexCollision>(p); }
double cast_bullet_gjk(const Pair& p) { return cast_bullet<btGjkConvexCast>(p); }

// ---- accuracy, against the exact reference ------------------------------------------------------

/// One library's accuracy on one benchmark's pairs: counters, in the order they are reported.
using Accuracy = std::vector<std::pair<std::string, double>>;

/// Errors of one library on one query, summed over the pairs.
struct Errors {
  int wrong = 0;  ///< wrong yes/no answers
  int n = 0;      ///< answers with a value to compare
  double sum = 0.0, max = 0.0;
  void add(double e) {
    e = std::fabs(e);
    ++n;
    sum += e;
    max = std::max(max, e);
  }
  [[nodiscard]] double mean() const { return n ? sum / n : 0.0; }
};

/// Lists the pairs a library answered wrongly (stderr), once per benchmark.
void list_wrong(const std::string& benchmark, const std::string& cases) {
  if (!cases.empty()) std::fprintf(stderr, "%s wrong:%s\n", benchmark.c_str(), cases.c_str());
}

std::string pair_case(size_t i, double truth) {
  return " #" + std::to_string(i) + " (exact " + std::to_string(truth) + ")";
}

Accuracy overlap_accuracy(const std::string& name, const std::vector<Pair>& pairs,
                          bool (*query)(const Pair&)) {
  Errors e;
  std::string cases;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const Pair& p = pairs[i];
    if (query(p) == p.overlapping) continue;
    ++e.wrong;
    cases += pair_case(i, p.k.depth());
  }
  list_wrong(name, cases);
  return {{"wrong", e.wrong}};
}

Accuracy distance_accuracy(const std::string& name, const std::vector<Pair>& pairs,
                           Closest (*query)(const Pair&)) {
  Errors e;
  double points = 0.0;
  std::string cases;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const Pair& p = pairs[i];
    const Closest d = query(p);
    if (d.distance <= 0.0) {
      ++e.wrong;
      cases += pair_case(i, p.distance);
      continue;
    }
    e.add(d.distance - p.distance);
    points = std::max({points, std::fabs(collide::test::brute_signed_distance(p.core_a, d.point_a)),
                       std::fabs(collide::test::brute_signed_distance(p.core_b, d.point_b)),
                       std::fabs(glm::length(d.point_a - d.point_b) - p.distance)});
  }
  list_wrong(name, cases);
  return {{"wrong", e.wrong}, {"max_err", e.max}, {"mean_err", e.mean()}, {"points_err", points}};
}

Accuracy depth_accuracy(const std::string& name, const std::vector<Pair>& pairs,
                        Depth (*query)(const Pair&), bool manifold) {
  Errors e;
  double normal_err = 0.0;
  int total_points = 0;
  std::string cases;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const Pair& p = pairs[i];
    const Depth d = query(p);
    if (!d.hit) {
      ++e.wrong;
      cases += pair_case(i, p.depth);
      continue;
    }
    e.add(d.depth - p.depth);
    total_points += d.points;
    const double len = glm::length(d.normal);
    normal_err = std::max(normal_err, len > 0.0 ? p.k.depth_along(d.normal / len) - p.depth : 1.0);
  }
  list_wrong(name, cases);
  Accuracy a{{"wrong", e.wrong}, {"max_err", e.max}, {"mean_err", e.mean()}, {"normal_err", normal_err}};
  if (manifold) a.emplace_back("points", e.n ? double(total_points) / e.n : 0.0);
  return a;
}

Accuracy cast_accuracy(const std::string& name, const std::vector<Pair>& pairs,
                       double (*query)(const Pair&)) {
  Errors e;
  int misses = 0, false_hits = 0;
  std::string cases;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const Pair& p = pairs[i];
    const double t = query(p);
    if (t >= 0.0 && p.touch < 0.0) {
      // A hit the reference does not have: wrong unless the shapes pass within 1e-4 there.
      Transform3 xa = p.xa;
      xa.p += static_cast<float>(t) * p.va;
      const double gap =
          collide::test::brute_core_distance(collide::test::brute_core(p.a->collide, xa),
                                             collide::test::brute_core(p.b->collide, p.xb));
      if (gap > 1e-4) {
        ++false_hits;
        cases += " #" + std::to_string(i) + " (false hit at " + std::to_string(t) + ")";
      }
      continue;
    }
    if (t < 0.0 && p.touch >= 0.0) {
      ++misses;
      cases += " #" + std::to_string(i) + " (missed " + std::to_string(p.touch) + ")";
      continue;
    }
    if (t >= 0.0) e.add((t - p.touch) * glm::length(p.va));  // as a distance along the motion
  }
  list_wrong(name, cases);
  return {{"misses", misses}, {"false_hits", false_hits}, {"max_err", e.max}, {"mean_err", e.mean()}};
}

void report_workload() {
  const Workload& w = workload();
  int sep_wrong = 0, ovl_wrong = 0, hits = 0;
  for (const Pair& p : w.separated) sep_wrong += p.overlapping;
  for (const Pair& p : w.overlapping) ovl_wrong += !p.overlapping;
  for (const Pair& p : w.approaching) hits += p.touch >= 0.0;
  const std::string text = std::to_string(w.hulls.size()) + " hulls (Jolt kept another vertex count on " +
                           std::to_string(w.jolt_vertex_mismatch) + "), " + std::to_string(kPairs) +
                           " pairs per set; exact reference: separated pairs overlapping " +
                           std::to_string(sep_wrong) + ", overlapping pairs apart " +
                           std::to_string(ovl_wrong) + ", approaching pairs that meet " +
                           std::to_string(hits);
  benchmark::AddCustomContext("workload", text);
}

// ---- timing -------------------------------------------------------------------------------------

/// Registers one benchmark: each iteration answers the query on every pair of the set; the
/// accuracy counters are computed on the first run and reported with every run.
template <class Result, class Check>
void register_batch(const std::string& name, const std::vector<Pair>* pairs,
                    Result (*query)(const Pair&), Check check) {
  auto accuracy = std::make_shared<std::optional<Accuracy>>();
  benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
    if (!*accuracy) *accuracy = check(name, *pairs, query);
    for (auto _ : state) {
      for (const Pair& p : *pairs) {
        Result r = query(p);
        benchmark::DoNotOptimize(r);
      }
    }
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs->size()));
    state.counters["per_query"] = benchmark::Counter(
        static_cast<double>(pairs->size()),
        benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    for (const auto& [counter, value] : **accuracy) state.counters[counter] = value;
  })->Unit(benchmark::kMicrosecond);
}

void overlap_batch(const std::string& name, const std::vector<Pair>* pairs,
                   bool (*query)(const Pair&)) {
  register_batch(name, pairs, query, overlap_accuracy);
}
void distance_batch(const std::string& name, const std::vector<Pair>* pairs,
                    Closest (*query)(const Pair&)) {
  register_batch(name, pairs, query, distance_accuracy);
}
void depth_batch(const std::string& name, const std::vector<Pair>* pairs,
                 Depth (*query)(const Pair&)) {
  register_batch(name, pairs, query, [](const std::string& n, const std::vector<Pair>& ps,
                                        Depth (*q)(const Pair&)) {
    return depth_accuracy(n, ps, q, false);
  });
}
void contact_batch(const std::string& name, const std::vector<Pair>* pairs,
                   Depth (*query)(const Pair&)) {
  register_batch(name, pairs, query, [](const std::string& n, const std::vector<Pair>& ps,
                                        Depth (*q)(const Pair&)) {
    return depth_accuracy(n, ps, q, true);
  });
}
void cast_batch(const std::string& name, const std::vector<Pair>* pairs,
                double (*query)(const Pair&)) {
  register_batch(name, pairs, query, cast_accuracy);
}

void register_all() {
  const Workload& w = workload();
  for (const auto& [set, pairs] : {std::pair{"separated", &w.separated},
                                   std::pair{"overlapping", &w.overlapping}}) {
    const std::string base = std::string("BM_Overlap/") + set + "/";
    overlap_batch(base + "collide", pairs, overlap_collide);
    overlap_batch(base + "jolt", pairs, overlap_jolt);
    overlap_batch(base + "libccd", pairs, overlap_ccd);
    overlap_batch(base + "fcl", pairs, overlap_fcl);
    overlap_batch(base + "bullet", pairs, overlap_bullet);
  }
  distance_batch("BM_Distance/separated/collide", &w.separated, distance_collide);
  distance_batch("BM_Distance/separated/jolt", &w.separated, distance_jolt);
  distance_batch("BM_Distance/separated/fcl_libccd", &w.separated, distance_fcl_ccd);
  distance_batch("BM_Distance/separated/fcl_indep", &w.separated, distance_fcl_indep);
  distance_batch("BM_Distance/separated/bullet", &w.separated, distance_bullet);
  depth_batch("BM_Depth/overlapping/collide_epa", &w.overlapping, depth_collide_epa);
  depth_batch("BM_Depth/overlapping/collide_contact", &w.overlapping, depth_collide_contact);
  depth_batch("BM_Depth/overlapping/jolt_epa", &w.overlapping, depth_jolt);
  depth_batch("BM_Depth/overlapping/libccd_gjk_epa", &w.overlapping, depth_ccd_gjk);
  depth_batch("BM_Depth/overlapping/libccd_mpr", &w.overlapping, depth_ccd_mpr);
  depth_batch("BM_Depth/overlapping/fcl", &w.overlapping, depth_fcl);
  depth_batch("BM_Depth/overlapping/bullet_epa", &w.overlapping, depth_bullet);
  contact_batch("BM_Contact/overlapping/collide", &w.overlapping, contact_collide);
  contact_batch("BM_Contact/overlapping/jolt", &w.overlapping, contact_jolt);
  contact_batch("BM_Contact/overlapping/bullet_sat", &w.overlapping, contact_bullet);
  cast_batch("BM_ShapeCast/approaching/collide", &w.approaching, cast_collide);
  cast_batch("BM_ShapeCast/approaching/jolt", &w.approaching, cast_jolt);
  cast_batch("BM_ShapeCast/approaching/bullet_continuous", &w.approaching, cast_bullet_continuous);
  cast_batch("BM_ShapeCast/approaching/bullet_gjk", &w.approaching, cast_bullet_gjk);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  collide::bench::add_instruction_sets("jolt", jolt_queries::instruction_set());
  benchmark::AddCustomContext("libccd, fcl, bullet",
                              "Debian packages, x86-64 baseline; libccd, FCL double; Bullet float");
  report_workload();
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
