#pragma once
/// @file
/// `time_of_impact`: when do two shapes that translate AND rotate over a step first come
/// within a small target separation of each other? With rotation the Minkowski difference
/// changes shape during the step, so the single ray of `shape_cast` no longer applies (the
/// lesson's closing remark on continuous collision). 2D shapes move along a `Sweep`, 3D shapes
/// along a `Sweep3` (a constant angular velocity about a fixed axis, any number of turns); one
/// loop serves both dimensions, with a motion bound per dimension.
///
/// Method: conservative advancement (Mirtich, "Impulse-based Dynamic Simulation of Rigid Body
/// Systems", 1996, 4.3; discussed in Catto, "Continuous Collision", GDC 2013). At the current
/// time t, GJK (run in A's frame, warm-started from the previous step's simplex) gives the
/// distance d between the cores and the unit normal n between their closest points. Along that
/// fixed n the gap between the two support planes (a lower bound of the distance, measured by
/// a support query on each body) closes over a further dt by at most the centres' relative
/// motion along n plus, for each body, a per-point bound of how far its turn can push its
/// extent along n (cos and sin bounded by their Taylor polynomials: a convex function of dt,
/// so its first root is bracketed by a tangent/chord round; in 3D the same polynomial, with
/// each point's turn about the body's fixed rotation axis, src/ccd/turn_bound.hpp). t advances
/// to where that bound could use up the gap: provably never past the first contact; it stops
/// when the shapes are within the target. A cruder bound, turn times the core's reach from its centre of rotation,
/// is kept as a floor for the step (in 3D: turn times the farthest core point's distance from
/// the axis). Each step is one warm-started GJK call.
///
/// Why not the separating-axis root finder of Box2D's b2TimeOfImpact (Catto 2013)? It checks
/// its axis only at the ends of the interval, so a body that turns a lot within one step can
/// sweep through another unseen (Box2D limits rotation per step for that reason); the test
/// `TimeOfImpact.OverlappedSeparatedAndSpinning` has such a case. Conservative advancement
/// cannot miss; its cost is more iterations when turning dominates near a graze (capped by
/// kToiMaxIterations, reported as max_iterations with a safe fraction).
///
/// Pure translations (both sweeps without rotation) take the faster GJK ray cast of
/// `shape_cast` instead, on the shapes grown by half the target each.

#include <collide/ccd/shape_cast.hpp>
#include <collide/ccd/sweep.hpp>
#include <collide/core/error.hpp>

#include <cmath>

namespace collide {

/// Default target separation of `time_of_impact`, as a fraction of the smaller shape's size
/// (its core's reach plus radius): the query stops when the shapes are this far apart, just
/// before touching, so a solver that moves them to the time of impact leaves a sliver of gap.
inline constexpr float kToiTargetSeparation = 1e-3f;

/// Smallest target, as a fraction of the coordinates' magnitude (positions of the sweeps plus
/// the shapes' sizes): below about 30 float ulps the distance itself is rounding noise. At
/// 1e4 from the origin the target is then at least 0.04. The target is also kept at least
/// twice GJK's touching tolerance (kRelativeTolerance of the two shapes' sizes).
inline constexpr float kToiRoundingTarget = 4e-6f;

/// The separation at the reported time is within this fraction of the target of the target.
inline constexpr float kToiToleranceFraction = 0.25f;

/// Cap on the advancement steps (one GJK distance each) of `time_of_impact`. Translation and
/// moderate turning take a handful; grazes of fast-spinning long bodies can take dozens.
inline constexpr int kToiMaxIterations = 100;

/// Result of `time_of_impact` in D dimensions. World space.
template <int D>
struct ToiResultN {
  /// hit: the shapes come within the target separation at `fraction` in (0, 1]. separated:
  /// they stay farther apart over the whole step (fraction = 1). overlapped: already within
  /// the target, or overlapping, at the start (fraction = 0). max_iterations: the iteration cap
  /// was reached (or rounding put the shapes closer than the target minus the tolerance);
  /// `fraction` is a time before which the shapes do not touch.
  QueryStatus status = QueryStatus::separated;
  float fraction = 1.0f;    ///< time of impact as a fraction of the step, [0, 1] (see status)
  float separation = 0.0f;  ///< distance between the shapes at `fraction` (0 when overlapping)
  /// Unit normal from A to B at `fraction`; zero when separated or the cores overlap.
  VecN<D> normal{0.0f};
  /// Midway between the shapes' closest points at `fraction`; zero when separated.
  VecN<D> point{0.0f};
  /// Advancement steps (GJK distance queries); for pure translation, the ray cast's
  /// iterations.
  int iterations = 0;
};

using ToiResult = ToiResultN<2>;   ///< 2D time of impact
using ToiResult3 = ToiResultN<3>;  ///< 3D time of impact

/// First time in [0, 1] at which proxy A moving along `sweep_a` and proxy B moving along
/// `sweep_b` come within `target` of each other (world units; a negative value means the
/// default, kToiTargetSeparation times the smaller shape's size; raised to the float
/// resolution of the problem, see kToiRoundingTarget), reported within
/// kToiToleranceFraction * target of it. Radii are included exactly. Conservative
/// advancement (Mirtich 1996); pure translations use the GJK ray cast (van den Bergen 2004).
/// Never allocates. Sweeps must be finite (COLLIDE_ASSERT only; the validated entry points
/// are `time_of_impact` on shapes).
[[nodiscard]] ToiResult time_of_impact(const ConvexProxy& a, const Sweep& sweep_a,
                                       const ConvexProxy& b, const Sweep& sweep_b,
                                       float target = -1.0f) noexcept;

/// `time_of_impact` for any pair of 2D shapes. Throws InvalidInput if a sweep value or the
/// target is not finite.
template <Shape2DType A, Shape2DType B>
[[nodiscard]] ToiResult time_of_impact(const A& a, const Sweep& sweep_a, const B& b,
                                       const Sweep& sweep_b, float target = -1.0f) {
  check_sweep(sweep_a, "sweep_a");
  check_sweep(sweep_b, "sweep_b");
  if (!std::isfinite(target)) throw InvalidInput("target: not finite");
  return time_of_impact(ConvexProxy(a), sweep_a, ConvexProxy(b), sweep_b, target);
}

/// `time_of_impact` for two polygons. Sharp polygons of up to 8 vertices that only translate
/// take the lesson's ray into A - B directly: Cyrus-Beck clipping of the step by A's and B's
/// edge normals, each axis's separation moved by the target (Ericson, Real-Time Collision
/// Detection, 5.3.8 and 5.5), exact up to rounding, with no iterations (`iterations` 0); the
/// polygons' `distance` at that time confirms it (corners meeting first go to the GJK ray
/// cast, as do starts and grazes within the tolerance band). Other pairs as above.
[[nodiscard]] ToiResult time_of_impact(const Polygon& a, const Sweep& sweep_a, const Polygon& b,
                                       const Sweep& sweep_b, float target = -1.0f);

/// `time_of_impact` for a circle and a polygon. When neither turns: the shape cast of the
/// circle grown by the target (the ray into the polygon rounded by the radii, exact up to
/// rounding, no iterations; Ericson, Real-Time Collision Detection, 5.5.7), `separation` the
/// target. Otherwise as above.
[[nodiscard]] ToiResult time_of_impact(const Circle& a, const Sweep& sweep_a, const Polygon& b,
                                       const Sweep& sweep_b, float target = -1.0f);
/// `time_of_impact` for a polygon and a circle: the circle-polygon answer seen from A.
[[nodiscard]] ToiResult time_of_impact(const Polygon& a, const Sweep& sweep_a, const Circle& b,
                                       const Sweep& sweep_b, float target = -1.0f);
/// `time_of_impact` for a capsule and a polygon. When neither turns: the shape cast of the
/// capsule grown by the target (the ray into B minus the capsule's segment, rounded by the
/// radii: exact up to rounding, no iterations), `separation` the target. Otherwise as above.
[[nodiscard]] ToiResult time_of_impact(const Capsule& a, const Sweep& sweep_a, const Polygon& b,
                                       const Sweep& sweep_b, float target = -1.0f);
/// `time_of_impact` for a polygon and a capsule: the capsule-polygon answer seen from A.
[[nodiscard]] ToiResult time_of_impact(const Polygon& a, const Sweep& sweep_a, const Capsule& b,
                                       const Sweep& sweep_b, float target = -1.0f);

/// `time_of_impact` for shapes whose types are known only at run time.
[[nodiscard]] ToiResult time_of_impact(const Shape2D& a, const Sweep& sweep_a, const Shape2D& b,
                                       const Sweep& sweep_b, float target = -1.0f);

/// First time in [0, 1] at which 3D proxy A moving along `sweep_a` and proxy B moving along
/// `sweep_b` come within `target` of each other: the contract of the 2D `time_of_impact`
/// (target default and floors, reported within kToiToleranceFraction * target of it, never
/// late, statuses, a safe fraction on max_iterations), by the same conservative advancement
/// with the 3D turn bound (Mirtich 1996); pure translations (both rotation vectors zero) use
/// the GJK ray cast `gjk_shape_cast<3>` (van den Bergen 2004). Never allocates. Proxies hold
/// 1..kMaxProxyPoints3 points; sweeps must be finite with unit q0 (COLLIDE_ASSERT only; the
/// validated entry points are `time_of_impact` on shapes).
[[nodiscard]] ToiResult3 time_of_impact(const ConvexProxy3& a, const Sweep3& sweep_a,
                                        const ConvexProxy3& b, const Sweep3& sweep_b,
                                        float target = -1.0f) noexcept;

/// `time_of_impact` for any pair of convex 3D shapes. Throws InvalidInput naming the field if a
/// sweep value or the target is not finite, or a sweep's q0 is not a unit quaternion.
template <Shape3DType A, Shape3DType B>
[[nodiscard]] ToiResult3 time_of_impact(const A& a, const Sweep3& sweep_a, const B& b,
                                        const Sweep3& sweep_b, float target = -1.0f) {
  check_sweep(sweep_a, "sweep_a");
  check_sweep(sweep_b, "sweep_b");
  if (!std::isfinite(target)) throw InvalidInput("target: not finite");
  return time_of_impact(ConvexProxy3(a), sweep_a, ConvexProxy3(b), sweep_b, target);
}

/// `time_of_impact` for 3D shapes whose types are known only at run time.
[[nodiscard]] ToiResult3 time_of_impact(const Shape3D& a, const Sweep3& sweep_a,
                                        const Shape3D& b, const Sweep3& sweep_b,
                                        float target = -1.0f);

}  // namespace collide
