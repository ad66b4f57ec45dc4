#include <collide/broad/registry.hpp>

#include <collide/broad/brute_force.hpp>
#include <collide/broad/dynamic_tree.hpp>
#include <collide/broad/hash_grid.hpp>
#include <collide/broad/hierarchical_grid.hpp>
#include <collide/broad/loose_grid.hpp>
#include <collide/broad/sorted_grid.hpp>
#include <collide/broad/sweep_and_prune.hpp>
#include <collide/broad/temporal_broad_phase.hpp>
#include <collide/core/error.hpp>

#include <array>
#include <string>
#include <vector>

namespace collide {

namespace {

constexpr std::array<BroadPhaseInfo, 8> kBroadPhases = {{
    {"hierarchical_grid",
     "grid levels 4x apart in cell size: any mix of object sizes (default)"},
    {"sorted_grid", "uniform grid, cell keys radix-sorted each frame: large worlds, similar sizes"},
    {"loose_grid", "uniform grid, one entry per box, counting-sorted: fastest full rebuild"},
    {"hash_grid", "the lesson's hashed uniform grid, done right: each pair once"},
    {"dynamic_tree", "incremental AABB tree with fattened boxes (as Box2D, Bullet)"},
    {"sweep_and_prune", "boxes insertion-sorted along the axis of largest spread"},
    {"temporal", "speed-bound broad phase; for one static frame, its candidate grid + checks"},
    {"brute_force", "every pair tested: the O(n^2) reference"},
}};

constexpr std::array<std::string_view, kBroadPhases.size()> kNames = [] {
  std::array<std::string_view, kBroadPhases.size()> names{};
  for (std::size_t i = 0; i < kBroadPhases.size(); ++i) names[i] = kBroadPhases[i].name;
  return names;
}();

template <class BP, int D>
PairList run(std::span<const AabbN<D>> boxes) {
  BP bp;
  bp.build(boxes);
  PairList pairs;
  bp.find_pairs(pairs);
  sort_pairs(pairs);
  return pairs;
}

template <int D>
PairList find_pairs_n(std::string_view name, std::span<const AabbN<D>> boxes) {
  if (name.empty()) name = kNames[0];
  if (name == "hierarchical_grid") return run<HierarchicalGridN<D>, D>(boxes);
  if (name == "sorted_grid") return run<SortedGridN<D>, D>(boxes);
  if (name == "loose_grid") return run<LooseGridN<D>, D>(boxes);
  if (name == "hash_grid") return run<HashGridN<D>, D>(boxes);
  if (name == "dynamic_tree") return run<DynamicTreeN<D>, D>(boxes);
  if (name == "sweep_and_prune") return run<SweepAndPruneN<D>, D>(boxes);
  if (name == "temporal") {
    TemporalBroadPhaseN<D> temporal;
    temporal.build(boxes, std::vector<float>(boxes.size(), 0.0f));
    PairList pairs;
    temporal.find_pairs(pairs);
    sort_pairs(pairs);
    return pairs;
  }
  if (name == "brute_force") return run<BruteForceN<D>, D>(boxes);
  std::string valid;
  for (const std::string_view n : kNames) {
    if (!valid.empty()) valid += ", ";
    valid += n;
  }
  throw InvalidInput("broadphase: unknown name \"" + std::string(name) + "\" (valid: " + valid +
                     ")");
}

}  // namespace

std::span<const BroadPhaseInfo> broadphases() noexcept { return kBroadPhases; }

std::span<const std::string_view> broadphase_names() noexcept { return kNames; }

PairList find_pairs(std::string_view name, std::span<const Aabb> boxes) {
  return find_pairs_n<2>(name, boxes);
}

PairList find_pairs(std::string_view name, std::span<const Aabb3> boxes) {
  return find_pairs_n<3>(name, boxes);
}

}  // namespace collide
