// Finite but extreme coordinates (issue 15): boxes near +-FLT_MAX, one box spanning the whole
// float range, worlds at 1e38 and 1e30, tiny boxes 1e30 from the origin, all of them mixed with
// ordinary boxes. Every broad phase, 2D and 3D, must give exactly brute force's pairs and query
// answers, on build and on update (a box moved to 1e38 and back). On the old code the grids
// never returned for one finite box near 2e38 (the world's extent overflowed to infinity and
// the grid-sizing loop never ended), so each structure runs in a child process under a watchdog
// (tests/support/watchdog.hpp): a hang fails the test naming the world instead of stopping the
// suite. The watchdog's limit is far above the work's duration and asserts nothing about speed.

#include <collide/broad/brute_force.hpp>
#include <collide/broad/dynamic_tree.hpp>
#include <collide/broad/hash_grid.hpp>
#include <collide/broad/hierarchical_grid.hpp>
#include <collide/broad/loose_grid.hpp>
#include <collide/broad/registry.hpp>
#include <collide/broad/sorted_grid.hpp>
#include <collide/broad/sweep_and_prune.hpp>
#include <collide/broad/temporal_broad_phase.hpp>

#include "support/broad_worlds.hpp"
#include "support/watchdog.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace collide {
namespace {

using test::Boxes;
using test::brute_pairs;

constexpr float kMax = std::numeric_limits<float>::max();

/// Seconds a structure may take on all the worlds before the watchdog calls it a hang (the work
/// takes well under a second in release, a few under the sanitizers).
constexpr int kWatchdogSeconds = 60;

/// TemporalBroadPhase as the other structures are driven: all objects at rest (speed bound 0),
/// each update one time unit later.
template <int D>
struct TemporalAdapter {
  TemporalBroadPhaseN<D> bp;
  double time = 0.0;
  void build(std::span<const AabbN<D>> boxes) {
    time = 0.0;
    bp.build(boxes, std::vector<float>(boxes.size(), 0.0f), time);
  }
  void update(std::span<const AabbN<D>> boxes) { bp.update(boxes, time += 1.0); }
  void find_pairs(PairList& pairs) { bp.find_pairs(pairs); }
  void query(const AabbN<D>& box, QueryCallback cb) const { bp.query(box, cb); }
  void query_point(const VecN<D>& p, QueryCallback cb) const { bp.query_point(p, cb); }
  void ray_cast(const RayN<D>& ray, RayCallback cb) const { bp.ray_cast(ray, cb); }
};

/// LooseGrid through its combined calls (build_and_find_pairs, update_and_find_pairs).
template <int D>
struct LooseCombined {
  LooseGridN<D> bp;
  PairList found;
  void build(std::span<const AabbN<D>> boxes) { bp.build_and_find_pairs(boxes, found); }
  void update(std::span<const AabbN<D>> boxes) { bp.update_and_find_pairs(boxes, found); }
  void find_pairs(PairList& pairs) const { pairs = found; }
  void query(const AabbN<D>& box, QueryCallback cb) const { bp.query(box, cb); }
  void query_point(const VecN<D>& p, QueryCallback cb) const { bp.query_point(p, cb); }
  void ray_cast(const RayN<D>& ray, RayCallback cb) const { bp.ray_cast(ray, cb); }
};

template <int D>
AabbN<D> cube(float lo, float hi) {
  return {VecN<D>(lo), VecN<D>(hi)};
}

/// A box of side `side` (at least the float spacing there: never empty of a point) at `centre`.
template <int D>
AabbN<D> box_around(const VecN<D>& centre, float side) {
  AabbN<D> b{centre, centre};
  for (int k = 0; k < D; ++k) {
    b.min[k] = centre[k] - 0.5f * side;
    b.max[k] = centre[k] + 0.5f * side;
  }
  return b;
}

/// n boxes with centres uniform in [-extent, extent]^D and sides in [lo, hi] (as multiples of
/// extent), computed so that nothing overflows: the scale of the worlds at 1e38 and 1e30.
template <int D>
Boxes<D> scaled_world(std::mt19937& rng, int n, float extent, float lo, float hi) {
  Boxes<D> boxes;
  for (int i = 0; i < n; ++i) {
    const VecN<D> c = test::random_vec<D>(rng, -1.0f, 1.0f) * extent;
    boxes.push_back(box_around<D>(c, test::uniform_f(rng, lo, hi) * extent));
  }
  return boxes;
}

/// The worlds of the issue and around it, each with ordinary boxes among the extreme ones.
template <int D>
std::vector<std::pair<std::string, Boxes<D>>> extreme_worlds() {
  std::mt19937 rng(1500 + D);
  std::vector<std::pair<std::string, Boxes<D>>> worlds;
  const Boxes<D> normal = test::uniform_world<D>(rng, 150, D == 2 ? 12.0f : 5.0f, 0.2f, 1.0f);
  const auto with_normal = [&](Boxes<D> boxes) {
    boxes.insert(boxes.end(), normal.begin(), normal.end());
    return boxes;
  };
  // The issue's line: a unit box and one finite box whose extent overflows float.
  worlds.emplace_back("unit_and_2e38", Boxes<D>{cube<D>(0.0f, 1.0f), cube<D>(-2e38f, 2e38f)});
  // The whole float range, alone and over ordinary boxes.
  worlds.emplace_back("whole_range", with_normal({cube<D>(-kMax, kMax)}));
  // Boxes touching +-FLT_MAX: thin slabs at the ends of the range, corners of it, points on it.
  {
    Boxes<D> b;
    b.push_back(cube<D>(0.99f * kMax, kMax));
    b.push_back(cube<D>(-kMax, -0.99f * kMax));
    b.push_back(cube<D>(kMax, kMax));                    // the corner point itself
    b.push_back(cube<D>(0.5f * kMax, kMax));             // overlaps both above
    b.push_back(cube<D>(-kMax, 0.0f));                   // reaches the ordinary boxes
    AabbN<D> slab = cube<D>(-kMax, kMax);
    slab.min[0] = slab.max[0] = kMax;                    // zero-width slab on x = FLT_MAX
    b.push_back(slab);
    AabbN<D> mixed = cube<D>(-1.0f, 1.0f);
    mixed.max[D - 1] = kMax;                             // ordinary on all axes but one
    b.push_back(mixed);
    worlds.emplace_back("near_flt_max", with_normal(b));
  }
  // Worlds of ordinary shape scaled to 1e38 and 1e30 (sides 1% to 20% of the extent).
  worlds.emplace_back("at_1e38", with_normal(scaled_world<D>(rng, 200, 1e38f, 0.01f, 0.2f)));
  worlds.emplace_back("at_1e30", with_normal(scaled_world<D>(rng, 200, 1e30f, 0.01f, 0.2f)));
  // Tiny boxes (a few float spacings, 2^77 at 1e30) 1e30 from the origin, on both sides, on a
  // lattice of spacings so that they touch and overlap exactly; the ordinary boxes at the origin.
  {
    Boxes<D> b;
    const float ulp = std::nextafter(1e30f, kMax) - 1e30f;
    std::uniform_int_distribution<int> step(0, 12), len(0, 3);
    for (int i = 0; i < 120; ++i) {
      const float sign = i % 2 == 0 ? 1.0f : -1.0f;
      AabbN<D> box;
      for (int k = 0; k < D; ++k) {
        box.min[k] = sign * 1e30f + static_cast<float>(step(rng)) * ulp;
        box.max[k] = box.min[k] + static_cast<float>(len(rng)) * ulp;
      }
      b.push_back(box);
    }
    worlds.emplace_back("tiny_at_1e30", with_normal(b));
  }
  // Boxes scattered over every decade of the float range (1e-30 to 3e38), both signs, each as
  // large as a fraction of its distance from the origin: most decades hold a few boxes, the
  // large ones overlap many.
  {
    Boxes<D> b;
    for (int i = 0; i < 200; ++i) {
      VecN<D> c;
      for (int k = 0; k < D; ++k) {
        const float mag = std::pow(10.0f, test::uniform_f(rng, -30.0f, 38.5f));
        c[k] = (rng() % 2 == 0 ? 1.0f : -1.0f) * std::min(mag, kMax);
      }
      float r = 0.0f;
      for (int k = 0; k < D; ++k) r = std::max(r, std::abs(c[k]));
      AabbN<D> box;
      for (int k = 0; k < D; ++k) {
        const float half = test::uniform_f(rng, 0.1f, 1.2f) * r;  // up to 1.2 * 3.4e38: clamped
        box.min[k] = std::max(-kMax, c[k] - std::min(half, kMax));
        box.max[k] = std::min(kMax, c[k] + std::min(half, kMax));
        if (!std::isfinite(box.min[k])) box.min[k] = -kMax;
        if (!std::isfinite(box.max[k])) box.max[k] = kMax;
      }
      b.push_back(box);
    }
    worlds.emplace_back("every_decade", with_normal(b));
  }
  // Ordinary world with a few extreme boxes among them, at the front, middle and back.
  {
    Boxes<D> b = normal;
    b.insert(b.begin(), cube<D>(1e38f, 1.5e38f));
    b.insert(b.begin() + 70, cube<D>(-3e38f, -2.9e38f));
    b.insert(b.begin() + 71, cube<D>(-3e38f, 3e38f));
    b.push_back(box_around<D>(VecN<D>(1e30f), 1e25f));
    b.push_back(box_around<D>(VecN<D>(1e30f), 0.0f));
    worlds.emplace_back("ordinary_with_outliers", b);
  }
  return worlds;
}

/// The ids found but not wanted and wanted but not found (both sorted), for a failure message.
std::string differences(const std::vector<int>& got, const std::vector<int>& want) {
  std::vector<int> extra, missing;
  std::set_difference(got.begin(), got.end(), want.begin(), want.end(), std::back_inserter(extra));
  std::set_difference(want.begin(), want.end(), got.begin(), got.end(), std::back_inserter(missing));
  std::string text = " (extra:";
  for (const int id : extra) text += " " + std::to_string(id);
  text += "; missing:";
  for (const int id : missing) text += " " + std::to_string(id);
  return text + ")";
}

/// Compares the structure's current answers with brute force on `boxes`; each difference is
/// described through `say`. Returns the number of expected pairs.
template <int D, class BP>
std::size_t check_answers(BP& bp, std::span<const AabbN<D>> boxes, const std::string& what,
                          std::mt19937& rng, const std::function<void(const std::string&)>& say) {
  const PairList expected = brute_pairs<D>(boxes);
  PairList pairs;
  bp.find_pairs(pairs);
  PairList sorted = pairs;
  sort_pairs(sorted);
  if (sorted != expected) {
    std::ostringstream os;
    os << "FAIL " << what << ": " << sorted.size() << " pairs, brute force " << expected.size();
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) os << " (a pair twice)";
    say(os.str() + "\n");
  }
  if (boxes.empty()) return expected.size();
  BruteForceN<D> brute;
  brute.build(boxes);
  // Queries: a box of the world grown by half, a point at a corner, a ray between two box centres
  // (when its translation is finite).
  for (int q = 0; q < 12; ++q) {
    const AabbN<D>& a = boxes[rng() % boxes.size()];
    const AabbN<D>& b = boxes[rng() % boxes.size()];
    std::vector<int> got, want;
    const auto collect = [](std::vector<int>& out) {
      return [&out](int id) {
        out.push_back(id);
        return true;
      };
    };
    const AabbN<D> qbox{a.min, glm::min(a.max, a.min + 0.5f * (a.max - a.min))};
    if (is_valid(qbox)) {
      bp.query(qbox, collect(got));
      brute.query(qbox, collect(want));
      std::sort(got.begin(), got.end());
      if (got != want) say("FAIL " + what + ": query " + std::to_string(q) + differences(got, want) + "\n");
    }
    got.clear();
    want.clear();
    bp.query_point(a.max, collect(got));
    brute.query_point(a.max, collect(want));
    std::sort(got.begin(), got.end());
    if (got != want) say("FAIL " + what + ": point query " + std::to_string(q) + differences(got, want) + "\n");
    const VecN<D> from = a.min + 0.5f * (a.max - a.min), to = b.min + 0.5f * (b.max - b.min);
    const RayN<D> ray{from, to - from};
    bool finite = true;
    for (int k = 0; k < D; ++k) finite = finite && std::isfinite(ray.translation[k]) && std::isfinite(from[k]);
    if (!finite) continue;
    got.clear();
    want.clear();
    bp.ray_cast(ray, [&](int id, float f) { got.push_back(id); return f; });
    brute.ray_cast(ray, [&](int id, float f) { want.push_back(id); return f; });
    std::sort(got.begin(), got.end());
    if (got != want) say("FAIL " + what + ": ray " + std::to_string(q) + differences(got, want) + "\n");
  }
  return expected.size();
}

/// Builds each extreme world and checks it; then, on an ordinary world, moves boxes out to 1e38,
/// across the whole range and back by update, checking every step. Runs in the child.
template <int D, class BP>
void check_all_worlds(const std::function<void(const std::string&)>& say) {
  std::mt19937 rng(7);
  std::size_t total = 0;
  for (const auto& [name, boxes] : extreme_worlds<D>()) {
    say("world " + name + "\n");
    BP bp;
    try {
      bp.build(boxes);
      const std::size_t n = check_answers<D>(bp, boxes, name + " build", rng, say);
      if (boxes.size() > 100 && (n == 0 || n >= boxes.size() * (boxes.size() - 1) / 2)) {
        say("FAIL " + name + ": the world has no pair or every pair\n");
      }
      total += n;
      // update with the same boxes, then with everything mirrored (other cells, same pairs)
      bp.update(boxes);
      check_answers<D>(bp, boxes, name + " update", rng, say);
      Boxes<D> mirrored = boxes;
      for (AabbN<D>& b : mirrored) b = {-b.max, -b.min};
      bp.update(mirrored);
      check_answers<D>(bp, mirrored, name + " update mirrored", rng, say);
    } catch (const std::exception& e) {
      say("FAIL " + name + ": threw " + e.what() + "\n");
    }
  }
  // An ordinary world; box 5 goes to 1e38 and back, box 9 spans the whole range and back,
  // box 11 to -3e38 (a tiny box there) and back; then all of them at once.
  say("world moving\n");
  const Boxes<D> start = test::uniform_world<D>(rng, 200, D == 2 ? 10.0f : 4.0f, 0.2f, 1.0f);
  BP bp;
  bp.build(start);
  check_answers<D>(bp, start, "moving start", rng, say);
  const std::vector<std::pair<int, AabbN<D>>> moves = {
      {5, cube<D>(1e38f, 1e38f + 1e36f)},
      {9, cube<D>(-kMax, kMax)},
      {11, box_around<D>(VecN<D>(-3e38f), 1e31f)},
  };
  for (std::size_t m = 0; m <= moves.size(); ++m) {
    Boxes<D> boxes = start;
    for (std::size_t j = 0; j < moves.size(); ++j) {
      if (m == moves.size() || j == m) boxes[std::size_t(moves[j].first)] = moves[j].second;
    }
    const std::string what = "moving step " + std::to_string(m);
    try {
      bp.update(boxes);
      check_answers<D>(bp, boxes, what + " out", rng, say);
      bp.update(start);
      check_answers<D>(bp, start, what + " back", rng, say);
    } catch (const std::exception& e) {
      say("FAIL " + what + ": threw " + e.what() + "\n");
    }
  }
  if (total == 0) say("FAIL no pairs in any world\n");
  say("done\n");
}

template <class BP, int Dim>
struct Case {
  using Type = BP;
  static constexpr int D = Dim;
};

template <class C>
class ExtremeCoordinates : public ::testing::Test {};

using Cases = ::testing::Types<
    Case<BruteForceN<2>, 2>, Case<BruteForceN<3>, 3>, Case<HashGridN<2>, 2>, Case<HashGridN<3>, 3>,
    Case<SortedGridN<2>, 2>, Case<SortedGridN<3>, 3>, Case<LooseGridN<2>, 2>, Case<LooseGridN<3>, 3>,
    Case<LooseCombined<2>, 2>, Case<LooseCombined<3>, 3>, Case<HierarchicalGridN<2>, 2>,
    Case<HierarchicalGridN<3>, 3>, Case<DynamicTreeN<2>, 2>, Case<DynamicTreeN<3>, 3>,
    Case<SweepAndPruneN<2>, 2>, Case<SweepAndPruneN<3>, 3>, Case<TemporalAdapter<2>, 2>,
    Case<TemporalAdapter<3>, 3>>;
TYPED_TEST_SUITE(ExtremeCoordinates, Cases);

// Every world through build, update and queries, against brute force, under the watchdog.
TYPED_TEST(ExtremeCoordinates, PairsAndQueriesMatchBruteForce) {
  const test::WatchedRun run = test::run_with_watchdog(kWatchdogSeconds, [](const auto& say) {
    check_all_worlds<TypeParam::D, typename TypeParam::Type>(say);
  });
  EXPECT_TRUE(run.finished) << run.report;
  EXPECT_EQ(run.report.find("FAIL"), std::string::npos) << run.report;
  EXPECT_NE(run.report.find("done"), std::string::npos) << run.report;
}

// The registry's find_pairs (what `collide query` answers "pairs" with) on the issue's line, for
// every name.
TEST(ExtremeCoordinates, RegistryAnswersTheIssuesLineForEveryBroadPhase) {
  const test::WatchedRun run = test::run_with_watchdog(kWatchdogSeconds, [](const auto& say) {
    const std::vector<Aabb> boxes2 = {cube<2>(0.0f, 1.0f), cube<2>(-2e38f, 2e38f)};
    const std::vector<Aabb3> boxes3 = {cube<3>(0.0f, 1.0f), cube<3>(-2e38f, 2e38f)};
    const PairList want = {{0, 1}};
    for (const std::string_view name : broadphase_names()) {
      say("broadphase " + std::string(name) + "\n");
      if (find_pairs(name, boxes2) != want) say("FAIL 2D " + std::string(name) + "\n");
      if (find_pairs(name, boxes3) != want) say("FAIL 3D " + std::string(name) + "\n");
    }
    say("done\n");
  });
  EXPECT_TRUE(run.finished) << run.report;
  EXPECT_EQ(run.report.find("FAIL"), std::string::npos) << run.report;
  EXPECT_NE(run.report.find("done"), std::string::npos) << run.report;
}

// The watchdog itself: it kills a child that never returns and says so, and lets one through
// that does (so the tests above could fail by a hang).
TEST(Watchdog, KillsAHangAndPassesAFinish) {
  const test::WatchedRun hang = test::run_with_watchdog(1, [](const auto& say) {
    say("started\n");
    for (;;) pause();  // never returns
  });
  EXPECT_FALSE(hang.finished);
  EXPECT_NE(hang.report.find("started"), std::string::npos);
  EXPECT_NE(hang.report.find("hang"), std::string::npos);
  const test::WatchedRun quick = test::run_with_watchdog(10, [](const auto& say) { say("ok\n"); });
  EXPECT_TRUE(quick.finished);
  EXPECT_EQ(quick.report, "ok\n");
}

}  // namespace
}  // namespace collide
