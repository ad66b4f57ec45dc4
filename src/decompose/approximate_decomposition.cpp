// Approximate convex decomposition of triangle meshes: best-first splitting of the mesh's solid
// grid nodes by axis-aligned planes, hulls from the nodes' closest surface points, concavity
// read off the distance field (see approximate_decomposition.hpp for the method and why).

#include <collide/decompose/approximate_decomposition.hpp>

#include <collide/core/error.hpp>
#include <collide/narrow/closest_point.hpp>
#include <collide/sdf/distance_field.hpp>
#include <collide/sdf/winding_tree.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

namespace collide {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Nodes beyond the mesh's bounds on each side: the hulls of the surface's closest points never
/// reach farther than the surface, and a node outside that box is never inside a hull; one ring
/// keeps the outermost solid nodes' outside neighbours on the grid.
constexpr int kDecompositionMargin = 2;

/// A piece with no volume of its own (a sheet seen from one side, a single node) is given one by
/// moving its points this many voxels each way along each axis (see piece_hull).
constexpr float kDecompositionSheetVoxels = 0.25f;

/// Jacobi sweeps of the 3x3 eigen-solver (each sweep squares the off-diagonal error: 8 reach
/// double precision from any start).
constexpr int kJacobiSweeps = 8;
/// A piece's principal axis is tried as a split direction (beside the three world axes) when its
/// largest direction cosine with an axis is below this: cos 15 degrees.
constexpr double kObliqueMaxCosine = 0.9659258;

/// A candidate plane's two hulls are built with at most this many vertices (quickhull adds the
/// farthest points first, so the capped hull is the full one's best approximation of that
/// size): the hull builds are most of the time of a split, and ranking the planes needs only
/// their shapes' gist. The chosen plane's pieces get their full hulls.
constexpr int kDecompositionCandidateVertices = 48;

/// The look-ahead (choose_split) takes another direction's best plane over the best one only
/// when, two splits ahead, it leaves at most this fraction of the best one's worst concavity:
/// a clear win (two limbs on a block: cut both limbs off together, then apart, instead of
/// halving the block with a limb on each half). A smaller margin lets it trade near-ties, where
/// the look-ahead's single next split is a poor guide: measured on rob, env, spider and Wuson at
/// 5-32 hulls, 0.75 made env and Wuson worse at 32 hulls; 0.35-0.5 change only what they should.
constexpr float kLookaheadGain = 0.5f;

/// A candidate split's two concavities are taken as equal (and the smaller hull volume wins)
/// within this fraction of a voxel: the field's distances are exact to float rounding near the
/// surface, so closer concavities are the same node.
constexpr float kConcavityTieVoxels = 1e-3f;

/// A point a hull is built from, with the grid node it belongs to (which side of a cut takes it).
struct HullPoint {
  Vec3 position;      ///< local (mesh storage) coordinates
  glm::ivec3 node;    ///< the node it was made for
};

/// One piece of the solid: grid nodes (ascending memory index) and the points its hull is made of.
struct Piece {
  std::vector<std::uint32_t> nodes;
  std::vector<HullPoint> points;
  std::optional<ConvexHull> hull;     ///< null when its points have no volume
  float concavity = 0.0f;             ///< field distance of the farthest outside node in the hull
  bool splittable = true;             ///< false once no plane could split it
};

/// The solid as grid nodes: the field, which nodes are solid, which piece owns each.
struct SolidGrid {
  FieldGrid3 grid;
  Vec3 local_origin{0.0f};            ///< node (0, 0, 0) in local coordinates
  std::vector<float> distance;        ///< signed distance per node
  std::vector<Vec3> closest;          ///< closest surface point per node, local coordinates
  std::vector<std::int32_t> owner;    ///< piece index per solid node, -1 outside the solid

  [[nodiscard]] Vec3 position(glm::ivec3 i) const noexcept { return local_origin + Vec3(i) * grid.voxel; }
  [[nodiscard]] glm::ivec3 coords(std::uint32_t index) const noexcept {
    const int nx = grid.dims.x, ny = grid.dims.y;
    const int x = static_cast<int>(index % static_cast<std::uint32_t>(nx));
    const std::uint32_t rest = index / static_cast<std::uint32_t>(nx);
    return {x, static_cast<int>(rest % static_cast<std::uint32_t>(ny)), static_cast<int>(rest / static_cast<std::uint32_t>(ny))};
  }
  [[nodiscard]] bool in_grid(glm::ivec3 i) const noexcept {
    return i.x >= 0 && i.y >= 0 && i.z >= 0 && i.x < grid.dims.x && i.y < grid.dims.y && i.z < grid.dims.z;
  }
};

constexpr std::array<glm::ivec3, 6> kNeighbours{glm::ivec3{-1, 0, 0}, glm::ivec3{1, 0, 0}, glm::ivec3{0, -1, 0},
                                                glm::ivec3{0, 1, 0},  glm::ivec3{0, 0, -1}, glm::ivec3{0, 0, 1}};

/// The hull of `points`, or null when they have no volume (fewer than 4, flat, too thin).
std::optional<ConvexHull> try_hull(std::span<const Vec3> points, int max_vertices) {
  if (points.size() < 4) return std::nullopt;
  try {
    HullOptions options;
    options.max_vertices = max_vertices;
    return make_convex_hull(points, options);
  } catch (const InvalidInput&) {
    return std::nullopt;
  }
}

/// The hull of a piece's (or a side's) points, moved by `shift` (to mesh space for the result).
/// A sheet thinner than a voxel seen from one side only has all its closest points on one face,
/// and a piece of a single node or a single row has too few points: no volume. Then every point
/// is also moved kDecompositionSheetVoxels along each axis both ways, so a thin feature gets a
/// hull about that thin. Null only when even that fails (no points).
std::optional<ConvexHull> piece_hull(std::span<const HullPoint> points, Vec3 shift, float voxel, int max_vertices,
                                     std::vector<Vec3>& scratch) {
  scratch.clear();
  for (const HullPoint& p : points) scratch.push_back(p.position + shift);
  std::optional<ConvexHull> hull = try_hull(scratch, max_vertices);
  if (hull || points.empty()) return hull;
  const float offset = kDecompositionSheetVoxels * voxel;
  for (const HullPoint& p : points) {
    for (int axis = 0; axis < 3; ++axis) {
      Vec3 d(0.0f);
      d[axis] = offset;
      scratch.push_back(p.position + shift + d);
      scratch.push_back(p.position + shift - d);
    }
  }
  return try_hull(scratch, max_vertices);
}

/// How far `hull` (local coordinates) reaches outside the mesh: the largest field distance of an
/// outside node inside it. Scans the nodes of the hull's bounds, the distance test first (most
/// nodes are inside the solid or no farther than the best so far), planes only for the rest.
float hull_concavity(const SolidGrid& solid, const ConvexHull& hull) {
  const float voxel = solid.grid.voxel;
  const glm::ivec3 lo = glm::max(glm::ivec3(glm::floor((hull.bounds.min - solid.local_origin) / voxel)), glm::ivec3(0));
  const glm::ivec3 hi = glm::min(glm::ivec3(glm::ceil((hull.bounds.max - solid.local_origin) / voxel)), solid.grid.dims - 1);
  float worst = 0.0f;
  for (int z = lo.z; z <= hi.z; ++z) {
    for (int y = lo.y; y <= hi.y; ++y) {
      const std::size_t row = solid.grid.index({0, y, z});
      for (int x = lo.x; x <= hi.x; ++x) {
        const float d = solid.distance[row + static_cast<std::size_t>(x)];
        if (!(d > worst)) continue;
        const Vec3 p = solid.position({x, y, z});
        bool inside = true;
        for (const HullFace& face : hull.faces) {
          if (glm::dot(face.normal, p) > face.offset + hull.tolerance) {
            inside = false;
            break;
          }
        }
        if (inside) worst = d;
      }
    }
  }
  return worst;
}

/// A piece's hull and concavity from its points (local coordinates).
void finish_piece(const SolidGrid& solid, Piece& piece, std::vector<Vec3>& scratch) {
  piece.hull = piece_hull(piece.points, Vec3(0.0f), solid.grid.voxel, kMaxHullVertices, scratch);
  piece.concavity = piece.hull ? hull_concavity(solid, *piece.hull) : 0.0f;
  if (!piece.hull) piece.splittable = false;
}

/// A direction planes are tried across: nodes whose position projects onto `normal` at most
/// `first + (k + 0.5) voxel` go left of plane k, k in [0, planes).
struct Direction {
  Vec3 normal{1.0f, 0.0f, 0.0f};  ///< unit
  float first = 0.0f;             ///< smallest projection of the piece's nodes
  int planes = 0;                 ///< planes between the piece's extreme nodes, a voxel apart
};

/// A candidate plane: direction `direction`, plane `k`.
struct Candidate {
  int direction = 0;
  int k = 0;
  float cost = std::numeric_limits<float>::infinity();    ///< max of the two concavities
  float low = std::numeric_limits<float>::infinity();     ///< min of the two concavities
  float volume = std::numeric_limits<float>::infinity();  ///< sum of the two hull volumes
};

/// A plane as the split applies it: left is dot(normal, position) <= offset.
struct SplitPlane {
  Vec3 normal;
  float offset;
  [[nodiscard]] bool left(Vec3 position) const noexcept { return glm::dot(normal, position) <= offset; }
};

SplitPlane plane_of(const std::vector<Direction>& directions, const Candidate& c, float voxel) {
  const Direction& d = directions[static_cast<std::size_t>(c.direction)];
  return {d.normal, d.first + (float(c.k) + 0.5f) * voxel};
}

/// The two sides' hull points for `plane`: the piece's own points by their node, plus the new
/// cut face: for each pair of the piece's neighbouring nodes across the plane, their midpoint
/// where it is inside the mesh; where it is not, surface points instead (solid nodes reach up
/// to kDecompositionSolidVoxels outside the surface, and their midpoints would let the hulls
/// poke out along the cut by up to that): each node's closest point on its own side, and where
/// the chord between the two meets the plane on both sides, so the hulls meet on the surface.
void split_points(const SolidGrid& solid, const Piece& piece, std::int32_t piece_id, const SplitPlane& plane,
                  std::vector<HullPoint>& left, std::vector<HullPoint>& right) {
  left.clear();
  right.clear();
  for (const HullPoint& p : piece.points) (plane.left(solid.position(p.node)) ? left : right).push_back(p);
  const float reach = solid.grid.voxel;  // a neighbour is a voxel away: nodes farther cannot cross
  // Only a step with a positive component along the normal can cross from left to right.
  std::array<glm::ivec3, 3> steps;
  int step_count = 0;
  for (const glm::ivec3& step : kNeighbours) {
    if (glm::dot(plane.normal, Vec3(step)) > 0.0f) steps[static_cast<std::size_t>(step_count++)] = step;
  }
  for (const std::uint32_t n : piece.nodes) {
    const glm::ivec3 i = solid.coords(n);
    const Vec3 pi = solid.position(i);
    const float side = glm::dot(plane.normal, pi) - plane.offset;
    if (side > 0.0f || side < -reach) continue;  // right of the plane, or too far left
    for (int s = 0; s < step_count; ++s) {
      const glm::ivec3& step = steps[static_cast<std::size_t>(s)];
      const glm::ivec3 j = i + step;
      if (!solid.in_grid(j)) continue;
      const std::size_t m = solid.grid.index(j);
      if (solid.owner[m] != piece_id) continue;
      const Vec3 pj = solid.position(j);
      if (plane.left(pj)) continue;
      if (solid.distance[n] + solid.distance[m] <= 0.0f) {  // the midpoint is inside the mesh
        const Vec3 mid = (pi + pj) * 0.5f;
        left.push_back({mid, i});
        right.push_back({mid, j});
      } else {  // outside (a node of the thin shell around the surface): surface points
        const Vec3 a = solid.closest[n], b = solid.closest[m];
        const float da = glm::dot(plane.normal, a) - plane.offset, db = glm::dot(plane.normal, b) - plane.offset;
        // Where the chord between the two surface points meets the plane (the end nearer to
        // it when it does not): the seam, on both sides, so the hulls meet on the surface.
        const float t = da != db ? std::clamp(da / (da - db), 0.0f, 1.0f) : 0.5f;
        const Vec3 seam = a + (b - a) * t;
        left.push_back({seam, i});
        right.push_back({seam, j});
        if (da <= 0.0f) left.push_back({a, i});
        if (db >= 0.0f) right.push_back({b, j});
      }
    }
  }
}

/// Concavity and volume of the two hulls of a candidate (infinite cost when a side has no
/// volume).
void evaluate(const SolidGrid& solid, const Piece& piece, std::int32_t piece_id, const SplitPlane& plane,
              Candidate& candidate, std::vector<HullPoint>& left, std::vector<HullPoint>& right,
              std::vector<Vec3>& scratch) {
  split_points(solid, piece, piece_id, plane, left, right);
  float cost = 0.0f, low = std::numeric_limits<float>::infinity(), volume = 0.0f;
  for (const std::vector<HullPoint>* side : {&left, &right}) {
    const std::optional<ConvexHull> hull =
        piece_hull(*side, Vec3(0.0f), solid.grid.voxel, kDecompositionCandidateVertices, scratch);
    if (!hull) return;
    const float concavity = hull_concavity(solid, *hull);
    cost = std::max(cost, concavity);
    low = std::min(low, concavity);
    volume += hull->volume;
  }
  candidate.cost = cost;
  candidate.low = low;
  candidate.volume = volume;
}

/// True when `a` is a better split than `b` (lower concavity; within the tie band, less hull
/// volume; then the earlier candidate, so the choice never depends on evaluation order).
bool better(const Candidate& a, const Candidate& b, float tie) {
  if (a.cost < b.cost - tie) return true;
  if (a.cost > b.cost + tie) return false;
  return a.volume < b.volume;
}

/// Per-worker buffers of the candidate evaluation.
struct Scratch {
  std::vector<HullPoint> left, right;
  std::vector<Vec3> points;
};

/// Evaluates `candidates` on the scheduler (each into its own slot) and returns the index of the
/// best, or -1 when none splits the piece into two solids.
int best_candidate(const SolidGrid& solid, const Piece& piece, std::int32_t piece_id,
                   const std::vector<Direction>& directions, std::vector<Candidate>& candidates,
                   std::vector<Scratch>& scratch, TaskScheduler* scheduler) {
  parallel_for(scheduler, static_cast<int>(candidates.size()), 1, [&](int begin, int end, int worker) {
    Scratch& s = scratch[static_cast<std::size_t>(worker)];
    for (int c = begin; c < end; ++c) {
      Candidate& candidate = candidates[static_cast<std::size_t>(c)];
      evaluate(solid, piece, piece_id, plane_of(directions, candidate, solid.grid.voxel), candidate, s.left,
               s.right, s.points);
    }
  });
  const float tie = kConcavityTieVoxels * solid.grid.voxel;
  int best = -1;
  for (int c = 0; c < static_cast<int>(candidates.size()); ++c) {
    if (!std::isfinite(candidates[static_cast<std::size_t>(c)].cost)) continue;
    if (best < 0 || better(candidates[static_cast<std::size_t>(c)], candidates[static_cast<std::size_t>(best)], tie)) best = c;
  }
  return best;
}

/// Eigenvectors of a symmetric 3x3 matrix (columns of the result), by cyclic Jacobi rotations
/// (Golub & Van Loan, Matrix Computations, 8.5; Ericson, Real-Time Collision Detection, 4.3.4).
/// In double; a fixed sweep count, so the same input gives the same output everywhere.
glm::dmat3 symmetric_eigenvectors(glm::dmat3 a) {
  glm::dmat3 v(1.0);
  for (int sweep = 0; sweep < kJacobiSweeps; ++sweep) {
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (std::abs(a[q][p]) < 1e-300) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[q][p]);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        glm::dmat3 rotation(1.0);
        rotation[p][p] = c;
        rotation[q][q] = c;
        rotation[q][p] = s;   // column q, row p
        rotation[p][q] = -s;  // column p, row q
        a = glm::transpose(rotation) * a * rotation;
        v = v * rotation;
      }
    }
  }
  return v;
}

/// The directions a piece is split across: the three axes, and its nodes' principal axis of
/// largest spread unless that lies within 15 degrees of an axis (kObliqueMaxCosine): a limb at
/// an angle, which axis planes would cut into a staircase. Principal axes: the eigenvectors of
/// the nodes' covariance (Ericson 4.3.2), signed so that the largest coordinate is positive.
/// (All three principal axes as directions cost 30-40% more time for the same results.)
std::vector<Direction> split_directions(const SolidGrid& solid, const Piece& piece) {
  std::vector<Vec3> normals{{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  if (piece.nodes.size() >= 4) {
    glm::dvec3 mean(0.0);
    for (const std::uint32_t n : piece.nodes) mean += glm::dvec3(solid.coords(n));
    mean /= double(piece.nodes.size());
    glm::dmat3 covariance(0.0);
    for (const std::uint32_t n : piece.nodes) {
      const glm::dvec3 d = glm::dvec3(solid.coords(n)) - mean;
      covariance += glm::outerProduct(d, d);
    }
    const glm::dmat3 axes = symmetric_eigenvectors(covariance);
    // The axis of largest spread (a limb's length): planes across it cut the limb off.
    int major = 0;
    double spread = -1.0;
    for (int k = 0; k < 3; ++k) {
      const double v = glm::dot(axes[k], covariance * axes[k]);
      if (v > spread) {
        spread = v;
        major = k;
      }
    }
    glm::dvec3 e = glm::normalize(axes[major]);
    const glm::dvec3 m = glm::abs(e);
    const double largest = std::max({m.x, m.y, m.z});
    if (largest < kObliqueMaxCosine) {  // not near an axis (the axis covers that), not NaN
      const int at = m.x == largest ? 0 : (m.y == largest ? 1 : 2);
      if (e[at] < 0.0) e = -e;
      normals.push_back(Vec3(e));
    }
  }
  std::vector<Direction> directions;
  const float voxel = solid.grid.voxel;
  for (const Vec3& normal : normals) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (const std::uint32_t n : piece.nodes) {
      const float x = glm::dot(normal, solid.position(solid.coords(n)));
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    directions.push_back({normal, lo, static_cast<int>(std::floor((hi - lo) / voxel))});
  }
  return directions;
}

/// `piece` (owner id `piece_id`) cut by `plane` into `left` and `right`: their nodes and hull
/// points (split_points); the right side's nodes are handed to owner `right_id`. No hulls yet.
void split_piece(SolidGrid& solid, const Piece& piece, std::int32_t piece_id, std::int32_t right_id,
                 const SplitPlane& plane, Piece& left, Piece& right) {
  split_points(solid, piece, piece_id, plane, left.points, right.points);
  for (const std::uint32_t n : piece.nodes) {
    if (plane.left(solid.position(solid.coords(n)))) {
      left.nodes.push_back(n);
    } else {
      right.nodes.push_back(n);
      solid.owner[n] = right_id;
    }
  }
}

/// The coarse candidates of `directions`: kDecompositionCoarsePlanes planes per direction,
/// evenly spaced; `steps` gets each direction's spacing (in planes).
std::vector<Candidate> coarse_candidates(const std::vector<Direction>& directions, std::vector<int>& steps) {
  std::vector<Candidate> candidates;
  steps.assign(directions.size(), 0);
  for (int d = 0; d < static_cast<int>(directions.size()); ++d) {
    const int planes = directions[static_cast<std::size_t>(d)].planes;
    if (planes < 1) continue;
    const int step = std::max(1, (planes + kDecompositionCoarsePlanes - 1) / kDecompositionCoarsePlanes);
    steps[static_cast<std::size_t>(d)] = step;
    for (int k = (step - 1) / 2; k < planes; k += step) candidates.push_back({d, k});
  }
  return candidates;
}

/// The worst concavity left two splits ahead when `piece` is split by `plane` and then the
/// worse of its two sides by its own best coarse plane (a depth-2 look-ahead, the idea of
/// CoACD's tree search at its smallest). The sides are made for real and undone: the right
/// side's nodes are owned by `free_id` meanwhile.
float two_step_concavity(SolidGrid& solid, const Piece& piece, std::int32_t piece_id, std::int32_t free_id,
                         const SplitPlane& plane, std::vector<Scratch>& scratch, TaskScheduler* scheduler,
                         int& evaluated) {
  Piece sides[2];
  split_piece(solid, piece, piece_id, free_id, plane, sides[0], sides[1]);
  float result = std::numeric_limits<float>::infinity();
  for (Piece& side : sides) {
    side.hull = piece_hull(side.points, Vec3(0.0f), solid.grid.voxel, kDecompositionCandidateVertices,
                           scratch[0].points);
    side.concavity = side.hull ? hull_concavity(solid, *side.hull) : 0.0f;
  }
  if (sides[0].hull && sides[1].hull) {
    const int worse = sides[1].concavity > sides[0].concavity ? 1 : 0;
    const Piece& w = sides[worse];
    float after = w.concavity;
    const std::vector<Direction> directions = split_directions(solid, w);
    std::vector<int> steps;
    std::vector<Candidate> candidates = coarse_candidates(directions, steps);
    if (!candidates.empty()) {
      const int best = best_candidate(solid, w, worse == 0 ? piece_id : free_id, directions, candidates, scratch,
                                      scheduler);
      evaluated += static_cast<int>(candidates.size());
      if (best >= 0) after = std::min(after, candidates[static_cast<std::size_t>(best)].cost);
    }
    result = std::max(sides[1 - worse].concavity, after);
  }
  for (const std::uint32_t n : sides[1].nodes) solid.owner[n] = piece_id;
  return result;
}

/// Of the coarse `candidates`, the one to split by two splits ahead: `best` (the greedy choice)
/// unless another direction's best plane leaves at most kLookaheadGain of best's worst
/// concavity after two_step_concavity. Only planes that could win are judged: a plane's better
/// side is left as it is (its two-step concavity is at least its `low`), and best's two-step
/// concavity is at most its cost.
Candidate look_ahead(SolidGrid& solid, const Piece& piece, std::int32_t piece_id, std::int32_t free_id,
                     const std::vector<Direction>& directions, const std::vector<Candidate>& candidates,
                     const Candidate& best, std::vector<Scratch>& scratch, TaskScheduler* scheduler, int& evaluated) {
  const float tie = kConcavityTieVoxels * solid.grid.voxel;
  std::vector<Candidate> leaders;
  for (int d = 0; d < static_cast<int>(directions.size()); ++d) {
    if (d == best.direction) continue;
    const Candidate* lead = nullptr;
    for (const Candidate& candidate : candidates) {
      if (candidate.direction != d || !std::isfinite(candidate.cost)) continue;
      if (!lead || better(candidate, *lead, tie)) lead = &candidate;
    }
    if (lead && lead->low < kLookaheadGain * best.cost) leaders.push_back(*lead);
  }
  if (leaders.empty()) return best;
  auto two_step = [&](const Candidate& c) {
    return two_step_concavity(solid, piece, piece_id, free_id, plane_of(directions, c, solid.grid.voxel), scratch,
                              scheduler, evaluated);
  };
  Candidate chosen = best;
  float bar = kLookaheadGain * two_step(best);
  for (const Candidate& leader : leaders) {
    if (!(leader.low < bar)) continue;
    const float ahead = two_step(leader);
    if (ahead < bar - tie) {
      bar = ahead;
      chosen = leader;
    }
  }
  return chosen;
}

/// The plane that splits `piece` best: a coarse pass of kDecompositionCoarsePlanes planes per
/// direction; the best plane of each direction is then judged two splits ahead
/// (two_step_concavity), and every plane between the winner's coarse neighbours is tried.
/// Null when none splits it.
std::optional<SplitPlane> choose_split(SolidGrid& solid, const Piece& piece, std::int32_t piece_id,
                                       std::int32_t free_id, std::vector<Scratch>& scratch, TaskScheduler* scheduler,
                                       int& evaluated) {
  const std::vector<Direction> directions = split_directions(solid, piece);
  std::vector<int> steps;
  std::vector<Candidate> candidates = coarse_candidates(directions, steps);
  if (candidates.empty()) return std::nullopt;
  const int best = best_candidate(solid, piece, piece_id, directions, candidates, scratch, scheduler);
  evaluated += static_cast<int>(candidates.size());
  if (best < 0) return std::nullopt;
  Candidate chosen = look_ahead(solid, piece, piece_id, free_id, directions, candidates,
                                candidates[static_cast<std::size_t>(best)], scratch, scheduler, evaluated);
  const float tie = kConcavityTieVoxels * solid.grid.voxel;
  const int step = steps[static_cast<std::size_t>(chosen.direction)];
  if (step > 1) {
    std::vector<Candidate> fine;
    const int planes = directions[static_cast<std::size_t>(chosen.direction)].planes;
    for (int k = std::max(0, chosen.k - step + 1); k <= std::min(planes - 1, chosen.k + step - 1); ++k) {
      if (k != chosen.k) fine.push_back({chosen.direction, k});
    }
    const int fine_best = best_candidate(solid, piece, piece_id, directions, fine, scratch, scheduler);
    evaluated += static_cast<int>(fine.size());
    if (fine_best >= 0 && better(fine[static_cast<std::size_t>(fine_best)], chosen, tie)) {
      chosen = fine[static_cast<std::size_t>(fine_best)];
    }
  }
  return plane_of(directions, chosen, solid.grid.voxel);
}

/// Splits pieces[index] by `plane` into itself (the left side) and a new piece at the back.
void apply_split(SolidGrid& solid, std::vector<Piece>& pieces, std::size_t index, const SplitPlane& plane,
                 std::vector<Vec3>& scratch) {
  Piece left, right;
  split_piece(solid, pieces[index], static_cast<std::int32_t>(index), static_cast<std::int32_t>(pieces.size()), plane,
              left, right);
  finish_piece(solid, left, scratch);
  finish_piece(solid, right, scratch);
  pieces[index] = std::move(left);
  pieces.push_back(std::move(right));
}

void check_options(const ApproximateDecompositionOptions& o) {
  if (o.max_hulls < 1 || o.max_hulls > kDecompositionMaxHulls) {
    throw InvalidInput("max_hulls: " + std::to_string(o.max_hulls) + " is outside [1, " +
                       std::to_string(kDecompositionMaxHulls) + "]");
  }
  if (!(o.concavity >= 0.0f) || !std::isfinite(o.concavity)) {
    throw InvalidInput("concavity: must be finite and >= 0, got " + std::to_string(o.concavity));
  }
  if (o.max_vertices < 4 || o.max_vertices > kMaxHullVertices) {
    throw InvalidInput("max_vertices: " + std::to_string(o.max_vertices) + " is outside [4, " +
                       std::to_string(kMaxHullVertices) + "]");
  }
  if (o.resolution < kDecompositionMinResolution || o.resolution > kDecompositionMaxResolution) {
    throw InvalidInput("resolution: " + std::to_string(o.resolution) + " is outside [" +
                       std::to_string(kDecompositionMinResolution) + ", " +
                       std::to_string(kDecompositionMaxResolution) + "]");
  }
  if (o.measure_samples < 0 || o.measure_samples > kDecompositionMaxSamples) {
    throw InvalidInput("measure_samples: " + std::to_string(o.measure_samples) + " is outside [0, " +
                       std::to_string(kDecompositionMaxSamples) + "]");
  }
}

/// The grid spacing for `resolution` nodes over a box of `extent` (all > 0):
/// cbrt(volume / resolution), but an axis thinner than the voxel counts as one node, and the
/// voxel is taken over the thicker axes alone (see ApproximateDecompositionOptions::resolution).
/// A 1000 x 1000 x 0.001 plate at 1e5 gets 3.2 (5e5 nodes with the margins), not 0.22 (1e8).
float decomposition_voxel(Vec3 extent, int resolution) {
  std::array<double, 3> e{extent.x, extent.y, extent.z};
  std::sort(e.begin(), e.end());
  const double n = resolution;
  double voxel = std::cbrt(e[0] * e[1] * e[2] / n);
  if (e[0] < voxel) {
    voxel = std::sqrt(e[1] * e[2] / n);
    if (e[1] < voxel) voxel = e[2] / n;
  }
  return static_cast<float>(voxel);
}

/// Which of the mesh's vertices its triangles use (`vertices` may hold unused ones).
std::vector<char> used_vertices(const TriangleMesh& mesh) {
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const glm::uvec3& t : mesh.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  return used;
}

/// splitmix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA
/// 2014): the same stream on every platform, unlike std's distributions.
struct SampleRng {
  std::uint64_t state;
  std::uint64_t next() noexcept {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1).
  float uniform() noexcept { return static_cast<float>(next() >> 40) * 0x1p-24f; }
};

/// A triangle to sample from and the running sum of areas up to and including it.
struct AreaTriangle {
  Vec3 a, b, c;
  double cumulative;
};

/// `count` points spread by area over `triangles` (uniform on the surface), appended to `out`.
void sample_triangles(const std::vector<AreaTriangle>& triangles, int count, SampleRng& rng, std::vector<Vec3>& out) {
  if (triangles.empty() || !(triangles.back().cumulative > 0.0)) return;
  const double total = triangles.back().cumulative;
  for (int s = 0; s < count; ++s) {
    const double target = static_cast<double>(rng.uniform()) * total;
    const auto it = std::upper_bound(triangles.begin(), triangles.end(), target,
                                     [](double v, const AreaTriangle& t) { return v < t.cumulative; });
    const AreaTriangle& t = it == triangles.end() ? triangles.back() : *it;
    float u = rng.uniform(), v = rng.uniform();
    if (u + v > 1.0f) {  // fold the far half of the parallelogram back onto the triangle
      u = 1.0f - u;
      v = 1.0f - v;
    }
    out.push_back(t.a + (t.b - t.a) * u + (t.c - t.a) * v);
  }
}

void push_area_triangle(std::vector<AreaTriangle>& list, Vec3 a, Vec3 b, Vec3 c) {
  const double area = 0.5 * static_cast<double>(glm::length(glm::cross(b - a, c - a)));
  list.push_back({a, b, c, (list.empty() ? 0.0 : list.back().cumulative) + area});
}

/// Volume bounded by a mesh by the divergence theorem (local coordinates): exact for a closed
/// surface whatever its triangulation (T-junctions and unwelded soups included); a hole's cap is
/// left out.
double closed_mesh_volume(const TriangleMesh& mesh) {
  double six_v = 0.0;
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 a(mesh.vertices[t[0]]), b(mesh.vertices[t[1]]), c(mesh.vertices[t[2]]);
    six_v += glm::dot(a, glm::cross(b, c));
  }
  return std::abs(six_v) / 6.0;
}

}  // namespace

ApproximateDecomposition decompose_approximate(const TriangleMesh& mesh, const ApproximateDecompositionOptions& options,
                                               std::optional<DecompositionProgress> progress) {
  const Clock::time_point start = Clock::now();
  check_options(options);
  if (mesh.triangles.empty()) throw InvalidInput("mesh: no triangles");
  const Aabb3 bounds = mesh.bvh.bounds();  // local: the triangles' corners
  const Vec3 extent = bounds.max - bounds.min;
  static constexpr std::array<const char*, 3> kAxisNames{"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    if (!(extent[k] > 0.0f)) throw InvalidInput(std::string("mesh: no volume (flat along ") + kAxisNames[static_cast<std::size_t>(k)] + ")");
  }

  ApproximateDecomposition result;
  result.diagonal = glm::length(extent);
  result.voxel = decomposition_voxel(extent, options.resolution);

  // The solid: the mesh's signed distance field and its closest points.
  const Clock::time_point field_start = Clock::now();
  FieldOptions field_options;
  field_options.voxel = result.voxel;
  field_options.margin = kDecompositionMargin;
  field_options.keep_closest_points = true;
  DistanceField3 field = make_distance_field(mesh, field_options);
  result.field_seconds = seconds_since(field_start);

  SolidGrid solid;
  solid.grid = field.grid;
  solid.local_origin = field.grid.origin - mesh.origin;
  solid.distance = std::move(field.distances);
  solid.closest = std::move(field.closest_points);
  for (Vec3& p : solid.closest) p -= mesh.origin;
  const std::size_t count = solid.grid.count();
  result.grid_nodes = static_cast<int>(count);
  const float solid_below = kDecompositionSolidVoxels * result.voxel;

  Piece root;
  solid.owner.assign(count, -1);
  for (std::size_t n = 0; n < count; ++n) {
    if (!(solid.distance[n] < solid_below)) continue;
    solid.owner[n] = 0;
    root.nodes.push_back(static_cast<std::uint32_t>(n));
  }
  result.solid_nodes = static_cast<int>(root.nodes.size());
  if (root.nodes.empty()) throw InvalidInput("mesh: no volume (no grid node inside it at voxel " + std::to_string(result.voxel) + ")");

  // Hull points: each solid node next to the outside gives its closest surface point; each mesh
  // vertex is given to its nearest solid node (sharp corners that no node sees).
  for (const std::uint32_t n : root.nodes) {
    const glm::ivec3 i = solid.coords(n);
    for (const glm::ivec3& step : kNeighbours) {
      const glm::ivec3 j = i + step;
      if (!solid.in_grid(j) || solid.owner[solid.grid.index(j)] < 0) {
        root.points.push_back({solid.closest[n], i});
        break;
      }
    }
  }
  {
    const std::vector<char> used = used_vertices(mesh);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      if (!used[v]) continue;
      const Vec3 p = mesh.vertices[v];
      const FieldCellN<3> cell = solid.grid.locate(p + mesh.origin);
      float best = std::numeric_limits<float>::infinity();
      glm::ivec3 owner_node(-1);
      for (int c = 0; c < 8; ++c) {
        const glm::ivec3 j = cell.node + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
        if (!solid.in_grid(j) || solid.owner[solid.grid.index(j)] < 0) continue;
        const Vec3 d = solid.position(j) - p;
        const float d2 = glm::dot(d, d);
        if (d2 < best) {
          best = d2;
          owner_node = j;
        }
      }
      if (owner_node.x >= 0) root.points.push_back({p, owner_node});
    }
  }

  std::vector<Piece> pieces;
  std::vector<Vec3> scratch_points;
  finish_piece(solid, root, scratch_points);
  if (!root.hull) throw InvalidInput("mesh: no volume (its solid is flat at voxel " + std::to_string(result.voxel) + ")");
  pieces.push_back(std::move(root));

  const int workers = options.scheduler ? std::max(1, options.scheduler->worker_count()) : 1;
  std::vector<Scratch> scratch(static_cast<std::size_t>(workers));
  const float bound = options.concavity * result.diagonal;
  while (static_cast<int>(pieces.size()) < options.max_hulls) {
    // The worst piece that can still be split (the first on ties: deterministic).
    int worst = -1;
    for (int p = 0; p < static_cast<int>(pieces.size()); ++p) {
      const Piece& piece = pieces[static_cast<std::size_t>(p)];
      if (!piece.splittable || !(piece.concavity > bound)) continue;
      if (worst < 0 || piece.concavity > pieces[static_cast<std::size_t>(worst)].concavity) worst = p;
    }
    if (worst < 0) break;
    const auto plane =
        choose_split(solid, pieces[static_cast<std::size_t>(worst)], worst, static_cast<std::int32_t>(pieces.size()),
                     scratch, options.scheduler, result.candidates);
    if (!plane) {
      pieces[static_cast<std::size_t>(worst)].splittable = false;
      continue;
    }
    apply_split(solid, pieces, static_cast<std::size_t>(worst), *plane, scratch_points);
    ++result.splits;
    if (progress) {
      float left = 0.0f;
      for (const Piece& piece : pieces) left = std::max(left, piece.concavity);
      (*progress)(static_cast<int>(pieces.size()), left);
    }
  }

  // The hulls in mesh space, capped at max_vertices.
  for (const Piece& piece : pieces) {
    result.grid_concavity = std::max(result.grid_concavity, piece.concavity);
    std::optional<ConvexHull> hull = piece_hull(piece.points, mesh.origin, solid.grid.voxel, options.max_vertices, scratch_points);
    if (hull) result.hulls.push_back(std::move(*hull));
  }
  if (result.hulls.empty()) throw InvalidInput("mesh: no volume (no piece has a hull)");

  if (options.measure_samples > 0) {
    const Clock::time_point measure_start = Clock::now();
    result.error = measure_decomposition(mesh, result.hulls, options.measure_samples, options.seed);
    result.measure_seconds = seconds_since(measure_start);
  }
  result.seconds = seconds_since(start);
  return result;
}

DecompositionError measure_decomposition(const TriangleMesh& mesh, std::span<const ConvexHull> hulls, int samples,
                                         std::uint64_t seed) {
  if (mesh.triangles.empty()) throw InvalidInput("mesh: no triangles");
  if (hulls.empty()) throw InvalidInput("hulls: none to measure");
  if (samples < 1 || samples > kDecompositionMaxSamples) {
    throw InvalidInput("samples: " + std::to_string(samples) + " is outside [1, " +
                       std::to_string(kDecompositionMaxSamples) + "]");
  }
  DecompositionError error;
  SampleRng rng{seed};

  // Hull surfaces against the solid (local coordinates, where the mesh's BVH and tree are).
  std::vector<AreaTriangle> hull_triangles;
  std::vector<Vec3> points;
  double hull_volume = 0.0;
  for (const ConvexHull& hull : hulls) {
    hull_volume += hull.volume;
    for (const Vec3& v : hull.vertices) points.push_back(v - mesh.origin);
    for (const HullFace& face : hull.faces) {
      const Vec3 a = hull.vertices[hull.face_vertices[face.first]] - mesh.origin;
      for (int k = 1; k + 1 < face.count; ++k) {
        push_area_triangle(hull_triangles, a, hull.vertices[hull.face_vertices[face.first + k]] - mesh.origin,
                           hull.vertices[hull.face_vertices[face.first + k + 1]] - mesh.origin);
      }
    }
  }
  sample_triangles(hull_triangles, samples, rng, points);
  const WindingTree winding(mesh.bvh);
  for (const Vec3& p : points) {
    if (winding(p) > 0.5f) continue;
    error.hull_to_mesh = std::max(error.hull_to_mesh, std::sqrt(mesh.bvh.nearest(p).distance_squared));
  }
  error.hull_samples = static_cast<int>(points.size());

  // The mesh's surface against the union of the hulls (mesh space, where the hulls are).
  std::vector<AreaTriangle> mesh_triangles;
  points.clear();
  for (const glm::uvec3& t : mesh.triangles) {
    push_area_triangle(mesh_triangles, mesh.vertices[t[0]] + mesh.origin, mesh.vertices[t[1]] + mesh.origin,
                       mesh.vertices[t[2]] + mesh.origin);
  }
  const std::vector<char> used = used_vertices(mesh);
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (used[v]) points.push_back(mesh.vertices[v] + mesh.origin);
  }
  sample_triangles(mesh_triangles, samples, rng, points);
  for (const Vec3& p : points) {
    float nearest = std::numeric_limits<float>::infinity();
    for (const ConvexHull& hull : hulls) {
      // The distance to the hull's box bounds the distance to the hull from below.
      const Vec3 out = glm::max(glm::max(hull.bounds.min - p, p - hull.bounds.max), Vec3(0.0f));
      if (glm::dot(out, out) >= nearest * nearest) continue;
      nearest = std::min(nearest, std::max(0.0f, closest_point(hull, Transform3{}, p).distance));
      if (nearest == 0.0f) break;
    }
    error.mesh_to_hull = std::max(error.mesh_to_hull, nearest);
  }
  error.mesh_samples = static_cast<int>(points.size());

  const double mesh_volume = closed_mesh_volume(mesh);
  error.volume_ratio = mesh_volume > 0.0 ? static_cast<float>(hull_volume / mesh_volume) : 0.0f;
  return error;
}

}  // namespace collide
