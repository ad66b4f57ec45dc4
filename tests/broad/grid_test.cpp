// The grids' own promises: the lesson's bugs stay fixed, cells chosen from the data, huge
// boxes kept out of the cells, cells widened for worlds far from the origin, levels for mixed
// sizes, ray walks exact along cell boundaries and through cell corners, and pair sets that do
// not change under rigid motions that map boxes to boxes.

#include <collide/broad/brute_force.hpp>
#include <collide/broad/dynamic_tree.hpp>
#include <collide/broad/hash_grid.hpp>
#include <collide/broad/hierarchical_grid.hpp>
#include <collide/broad/loose_grid.hpp>
#include <collide/broad/registry.hpp>
#include <collide/broad/sorted_grid.hpp>
#include <collide/core/error.hpp>

#include "support/allocation_counter.hpp"
#include "support/broad_worlds.hpp"
#include "support/test_scheduler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

namespace collide {
namespace {

using test::brute_pairs;

template <class BP, int D>
PairList pairs_of(BP& bp, std::span<const AabbN<D>> boxes) {
  bp.build(boxes);
  PairList pairs;
  bp.find_pairs(pairs);
  sort_pairs(pairs);
  return pairs;
}

template <class BP, int D>
PairList pairs_of_update(BP& bp, std::span<const AabbN<D>> boxes) {
  bp.update(boxes);
  PairList pairs;
  bp.find_pairs(pairs);
  sort_pairs(pairs);
  return pairs;
}

// cell_of clamps before it truncates (no floor): the cell must be floor-then-clamp's for every
// input, including the ones a floor treats differently from truncation (negatives, -0, values
// just below a cell boundary) and the ones no cell holds (NaN and the infinities land on a
// border cell, never in an undefined conversion).
TEST(GridMapping, CellOfIsFloorThenClampForEveryInput) {
  const GridMapping<2> m = make_grid_mapping<2>(Aabb{{-3.0f, 5.0f}, {7.0f, 9.5f}}, 0.75f);
  const auto reference = [&](Vec2 p) {
    CellN<2> c;
    for (int k = 0; k < 2; ++k) {
      const double v = std::floor(static_cast<double>((p[k] - m.origin[k]) * m.inv_cell_size));
      c[k] = std::isnan(v) || v < 0.0 ? 0 : static_cast<int>(std::min(v, static_cast<double>(m.dims[k] - 1)));
    }
    return c;
  };
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> xs{std::numeric_limits<float>::quiet_NaN(), -inf, inf, -0.0f, 0.0f, -1e30f, 1e30f};
  for (int i = -8; i <= 24; ++i) {  // every cell boundary of both axes and the floats beside it
    for (int k = 0; k < 2; ++k) {
      const float edge = m.origin[k] + static_cast<float>(i) * m.cell_size;
      xs.insert(xs.end(), {edge, std::nextafter(edge, -inf), std::nextafter(edge, inf)});
    }
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> wide(-20.0f, 30.0f);
  for (int i = 0; i < 2000; ++i) xs.push_back(wide(rng));
  int on_border = 0;
  for (const float x : xs) {
    for (const float y : {x, 6.0f, std::numeric_limits<float>::quiet_NaN()}) {
      const Vec2 p{x, y};
      const CellN<2> c = m.cell_of(p);
      EXPECT_EQ(c, reference(p)) << p.x << " " << p.y;
      on_border += c.x == 0 || c.x == m.dims.x - 1;
    }
  }
  EXPECT_GT(on_border, 100);  // the clamps were reached
}

/// The slab method in double, written out per axis (Ericson 5.3.3): the fractions in [0,
/// max_fraction] where the ray enters and leaves the closed box (enter > leave on a miss); an
/// axis the ray does not move along needs the origin inside that slab.
template <int D>
std::pair<double, double> slab_interval_reference(const RayN<D>& ray, const AabbN<D>& box, double max_fraction) {
  double enter = 0.0, leave = max_fraction;
  for (int k = 0; k < D; ++k) {
    const double o = ray.origin[k], d = ray.translation[k];
    if (d == 0.0) {
      if (o < box.min[k] || o > box.max[k]) return {1.0, -1.0};
      continue;
    }
    double t0 = (box.min[k] - o) / d, t1 = (box.max[k] - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  }
  return {enter, leave};
}

/// The entry fraction of slab_interval_reference, or -1 on a miss (ray_box_fraction's contract).
template <int D>
double slab_fraction_reference(const RayN<D>& ray, const AabbN<D>& box, double max_fraction) {
  const auto [enter, leave] = slab_interval_reference(ray, box, max_fraction);
  return enter <= leave ? enter : -1.0;
}

// SlabRayN (every grid's and tree's ray test) against the slab method in double, on rays along
// no axis, along one or two axes, starting inside boxes and grazing them: the same hit or miss
// except where the ray passes within rounding of a box's edge, and the same fraction.
TEST(SlabRay, FractionMatchesTheSlabMethodInDouble) {
  std::mt19937 rng(86);
  std::uniform_real_distribution<float> coord(-10.0f, 10.0f), size(0.01f, 4.0f), frac(0.0f, 1.0f);
  int hits = 0, misses = 0, inside = 0, grazing = 0;
  for (int i = 0; i < 20000; ++i) {
    Aabb3 box;
    for (int k = 0; k < 3; ++k) {
      box.min[k] = coord(rng);
      box.max[k] = box.min[k] + size(rng);
    }
    Ray3 ray{{coord(rng), coord(rng), coord(rng)}, {coord(rng), coord(rng), coord(rng)}};
    if (i % 2 == 0) {  // aimed past a point near the box: about half of these hit
      const Vec3 near_box = box.min + (box.max - box.min) * Vec3(frac(rng), frac(rng), frac(rng)) * 1.6f - 0.3f * (box.max - box.min);
      ray.translation = 1.5f * (near_box - ray.origin);
    }
    if (i % 4 == 1) ray.translation[i % 3] = 0.0f;  // along a plane
    if (i % 8 == 3) ray.translation[(i + 1) % 3] = ray.translation[(i + 2) % 3] = 0.0f;  // along an axis
    if (i % 16 == 5) ray.origin = 0.5f * (box.min + box.max);  // from inside
    const float max_fraction = i % 2 == 0 ? 1.0f : frac(rng);
    const float got = SlabRayN<3>(ray).fraction(box, max_fraction);
    const double want = slab_fraction_reference(ray, box, max_fraction);
    if ((got >= 0.0f) != (want >= 0.0)) {
      // Only a ray within rounding of the box's boundary may be judged differently: grow and
      // shrink the box by a hair and the double test must disagree with itself.
      Aabb3 grown = box, shrunk = box;
      for (int k = 0; k < 3; ++k) {
        const float pad = 1e-4f * (1.0f + std::abs(box.min[k]) + std::abs(box.max[k]));
        grown.min[k] -= pad;
        grown.max[k] += pad;
        shrunk.min[k] += pad;
        shrunk.max[k] -= pad;
      }
      EXPECT_GE(slab_fraction_reference(ray, grown, max_fraction), 0.0) << i;
      EXPECT_LT(slab_fraction_reference(ray, shrunk, max_fraction), 0.0) << i;
      ++grazing;
      continue;
    }
    if (want < 0.0) {
      ++misses;
      continue;
    }
    ++hits;
    inside += want == 0.0;
    EXPECT_NEAR(got, want, 1e-5 * (1.0 + std::abs(want)) + 1e-6) << i;
  }
  EXPECT_GT(hits, 2000);
  EXPECT_GT(misses, 2000);
  EXPECT_GT(inside, 500);
  EXPECT_LT(grazing, 20);
}

// walk_cells (every grid's ray walk) against the cells' own boxes: it visits each cell the ray
// crosses with some length inside, once, in order along the ray, and no cell the ray passes far
// from; walk_length bounds the count. Rays along no axis and along planes, inside and beyond the
// grid, with a walk clipped by max_fraction.
TEST(GridMapping, WalkCellsVisitsTheCellsTheRayCrossesInOrder) {
  const GridMapping<3> g = make_grid_mapping<3>(Aabb3{{-4.0f, -3.0f, -2.0f}, {6.0f, 5.0f, 3.5f}}, 0.7f);
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> coord(-8.0f, 9.0f), frac(0.2f, 1.0f);
  const auto cell_box = [&](const CellN<3>& c) {
    Aabb3 b;
    for (int k = 0; k < 3; ++k) {
      b.min[k] = g.origin[k] + static_cast<float>(c[k]) * g.cell_size;
      b.max[k] = b.min[k] + g.cell_size;
    }
    return b;
  };
  // The length of the ray's part inside box b, in fractions (negative if it misses).
  const auto inside_length = [](const Ray3& ray, const Aabb3& b, double max_fraction) {
    const auto [enter, leave] = slab_interval_reference(ray, b, max_fraction);
    return leave - enter;
  };
  int walked = 0;
  for (int i = 0; i < 400; ++i) {
    Ray3 ray{{coord(rng), coord(rng), coord(rng)}, {coord(rng), coord(rng), coord(rng)}};
    if (i % 2 == 0) {  // aimed through a point of the grid
      const Vec3 target = g.bounds.min + (g.bounds.max - g.bounds.min) * Vec3(frac(rng), frac(rng), frac(rng));
      ray.translation = 1.5f * (target - ray.origin);
    }
    if (i % 5 == 2) ray.translation[i % 3] = 0.0f;
    const float max_fraction = i % 3 == 0 ? frac(rng) : 1.0f;
    std::vector<CellN<3>> visited;
    std::vector<double> entered;
    walk_cells(g, ray, max_fraction, [&](const CellN<3>& c, float limit) {
      visited.push_back(c);
      entered.push_back(std::max(0.0, slab_fraction_reference(ray, cell_box(c), max_fraction)));
      return limit;
    });
    const double bound = walk_length(g, ray, max_fraction);
    EXPECT_LE(static_cast<double>(visited.size()), bound) << i;
    walked += !visited.empty();
    for (std::size_t v = 0; v < visited.size(); ++v) {
      // Touched (within rounding), in order, once.
      Aabb3 grown = cell_box(visited[v]);
      grown.min -= Vec3(1e-4f);
      grown.max += Vec3(1e-4f);
      EXPECT_GE(slab_fraction_reference(ray, grown, max_fraction), 0.0) << i << " cell " << v;
      if (v > 0) EXPECT_GE(entered[v], entered[v - 1] - 1e-6) << i << " cell " << v;
      for (std::size_t u = 0; u < v; ++u) EXPECT_NE(visited[u], visited[v]) << i;
    }
    // Every cell the ray crosses with some length (away from rounding) is visited.
    for (int x = 0; x < g.dims.x; ++x) {
      for (int y = 0; y < g.dims.y; ++y) {
        for (int z = 0; z < g.dims.z; ++z) {
          const CellN<3> c{x, y, z};
          // (the part of the cell inside the grid's bounds: the walk starts where the ray enters them)
          Aabb3 part = cell_box(c);
          part.min = glm::max(part.min, g.bounds.min);
          part.max = glm::min(part.max, g.bounds.max);
          if (!(part.min.x <= part.max.x && part.min.y <= part.max.y && part.min.z <= part.max.z)) continue;
          const double length = inside_length(ray, part, max_fraction) * glm::length(glm::dvec3(ray.translation));
          if (length > 1e-3) {
            EXPECT_NE(std::find(visited.begin(), visited.end(), c), visited.end())
                << i << " misses cell " << x << "," << y << "," << z;
          }
        }
      }
    }
  }
  EXPECT_GT(walked, 200);
}

// Regression for the lesson's exercise: two boxes sharing 25 cells were reported 25 times.
TEST(HashGrid, PairSharingManyCellsIsReportedOnce) {
  const std::vector<Aabb> boxes = {{{0.0f, 0.0f}, {5.0f, 5.0f}}, {{0.5f, 0.5f}, {4.5f, 4.5f}}};
  HashGrid grid({.cell_size = 1.0f});
  EXPECT_EQ((pairs_of<HashGrid, 2>(grid, boxes)), (PairList{{0, 1}}));
  SortedGrid sorted({.cell_size = 1.0f});
  EXPECT_EQ((pairs_of<SortedGrid, 2>(sorted, boxes)), (PairList{{0, 1}}));
}

// Regression for the lesson's exercise: with a map instead of a multimap, a cell kept one box.
TEST(HashGrid, ManyBoxesInOneCellAllPair) {
  const std::vector<Aabb3> boxes(6, Aabb3{{0.1f, 0.1f, 0.1f}, {0.2f, 0.2f, 0.2f}});
  HashGrid3 grid({.cell_size = 1.0f});
  EXPECT_EQ((pairs_of<HashGrid3, 3>(grid, boxes).size()), 15u);
}

// Boxes whose faces, edges and corners lie exactly on cell boundaries, for several cell sizes
// (the lesson's "shouldn't max use ceil?").
TEST(HashGrid, TouchingOnCellBoundaries) {
  std::mt19937 rng(8);
  const auto boxes2 = test::touching_world<2>(rng, 400, 12);
  const auto boxes3 = test::touching_world<3>(rng, 400, 6);
  const PairList want2 = brute_pairs<2>(boxes2), want3 = brute_pairs<3>(boxes3);
  ASSERT_GT(want2.size(), 200u);
  ASSERT_GT(want3.size(), 100u);
  for (const float cell : {0.5f, 1.0f, 2.0f, 3.0f}) {
    HashGrid h2({.cell_size = cell});
    HashGrid3 h3({.cell_size = cell});
    SortedGrid s2({.cell_size = cell});
    SortedGrid3 s3({.cell_size = cell});
    HierarchicalGrid g2({.base_cell_size = cell});
    HierarchicalGrid3 g3({.base_cell_size = cell});
    EXPECT_EQ((pairs_of<HashGrid, 2>(h2, boxes2)), want2) << cell;
    EXPECT_EQ((pairs_of<HashGrid3, 3>(h3, boxes3)), want3) << cell;
    EXPECT_EQ((pairs_of<SortedGrid, 2>(s2, boxes2)), want2) << cell;
    EXPECT_EQ((pairs_of<SortedGrid3, 3>(s3, boxes3)), want3) << cell;
    EXPECT_EQ((pairs_of<HierarchicalGrid, 2>(g2, boxes2)), want2) << cell;
    EXPECT_EQ((pairs_of<HierarchicalGrid3, 3>(g3, boxes3)), want3) << cell;
  }
}

TEST(HashGrid, CellSizeIsChosenFromTheData) {
  std::vector<Aabb> boxes;
  for (int i = 0; i < 100; ++i) {
    const float x = static_cast<float>(i % 10) * 3.0f, y = static_cast<float>(i / 10) * 3.0f;
    const float side = i < 60 ? 2.0f : 0.5f;  // median largest side 2
    boxes.push_back({{x, y}, {x + side, y + side}});
  }
  HashGrid grid;
  grid.build(boxes);
  EXPECT_FLOAT_EQ(grid.grid().cell_size, 4.0f);
  EXPECT_EQ(grid.oversized_count(), 0);
}

TEST(HashGrid, HugeBoxesStayOutOfTheCells) {
  std::mt19937 rng(2);
  auto boxes = test::huge_object_world<2>(rng, 500, 40.0f);
  HashGrid grid;
  SortedGrid sorted;
  const PairList want = brute_pairs<2>(boxes);
  EXPECT_EQ((pairs_of<HashGrid, 2>(grid, boxes)), want);
  EXPECT_EQ((pairs_of<SortedGrid, 2>(sorted, boxes)), want);
  EXPECT_EQ(grid.oversized_count(), 4);
  EXPECT_EQ(sorted.oversized_count(), 4);
  EXPECT_LT(grid.cell_count(), 2000);
}

TEST(HashGrid, RejectsBadOptions) {
  EXPECT_THROW(HashGrid({.cell_size = -1.0f}), InvalidInput);
  EXPECT_THROW(HashGrid({.cell_size = std::nanf("")}), InvalidInput);
  EXPECT_THROW(HashGrid({.cell_size = 1.0f, .max_cells_per_box = 0}), InvalidInput);
  EXPECT_THROW(SortedGrid({.cell_size = -1.0f}), InvalidInput);
  EXPECT_THROW(HierarchicalGrid({.base_cell_size = -1.0f}), InvalidInput);
  EXPECT_THROW(DynamicTree({.margin = -1.0f}), InvalidInput);
}

TEST(HashGrid, ReserveMakesLaterBuildsAllocationFree) {
  std::mt19937 rng(6);
  const auto boxes = test::uniform_world<2>(rng, 1000, 30.0f, 0.1f, 1.0f);
  HashGrid grid;
  grid.reserve(1000, 8000);
  const std::size_t reserved = grid.memory_bytes();
  grid.build(boxes);
  PairList pairs;
  grid.find_pairs(pairs);
  EXPECT_EQ(grid.memory_bytes(), reserved);
  EXPECT_FALSE(pairs.empty());
}

// A world spanning +-1e6 with a cell size the coordinates cannot resolve: the grid widens its
// cells until the linear cell index fits, and stays exact.
TEST(SortedGrid, WorldsFarFromTheOriginWidenTheCells) {
  std::mt19937 rng(17);
  auto boxes2 = test::uniform_world<2>(rng, 400, 1.0e6f, 1.0f, 20.0f);
  auto cluster2 = test::uniform_world<2>(rng, 200, 50.0f, 0.5f, 2.0f, 9.9e5f);
  boxes2.insert(boxes2.end(), cluster2.begin(), cluster2.end());
  auto boxes3 = test::uniform_world<3>(rng, 400, 1.0e6f, 1.0f, 20.0f);
  auto cluster3 = test::uniform_world<3>(rng, 200, 10.0f, 0.5f, 2.0f, -9.9e5f);
  boxes3.insert(boxes3.end(), cluster3.begin(), cluster3.end());
  SortedGrid s2({.cell_size = 1e-3f});
  SortedGrid3 s3({.cell_size = 1e-3f});
  const PairList want2 = brute_pairs<2>(boxes2), want3 = brute_pairs<3>(boxes3);
  ASSERT_GT(want2.size(), 50u);
  ASSERT_GT(want3.size(), 50u);
  EXPECT_EQ((pairs_of<SortedGrid, 2>(s2, boxes2)), want2);
  EXPECT_EQ((pairs_of<SortedGrid3, 3>(s3, boxes3)), want3);
  EXPECT_GT(s2.grid().cell_size, 1e-3f);
  EXPECT_GT(s3.grid().cell_size, 0.5f);  // 2e6 / 2^21 cells per axis in 3D
  HashGrid h2({.cell_size = 1e-3f});
  EXPECT_EQ((pairs_of<HashGrid, 2>(h2, boxes2)), want2);
}

// A cell's entries come from the counting sort's offsets when the grid is dense and from a
// binary search over the runs when it is sparse: both answer box queries as brute force does,
// and a cell holds exactly the boxes whose cell range covers it (none outside the grid).
// A sparse grid's cells are found by binary search behind a bitmap of occupied blocks: a cell a
// bit when the grid has at most kBlockBitsPerBox cells a box (`sparse`), else blocks of 2^k
// cells a side (`finest`); every cell's entries, box queries and rays as the dense grid's.
TEST(SortedGrid, DenseAndSparseGridsFindTheSameCellsAndQueries) {
  std::mt19937 rng(23);
  const auto boxes = test::uniform_world<2>(rng, 500, 100.0f, 0.5f, 4.0f);
  SortedGrid dense({.cell_size = 5.0f});
  SortedGrid sparse({.cell_size = 1.5f});
  SortedGrid finest({.cell_size = 0.25f, .max_cells_per_box = 1 << 20});  // none oversized
  dense.build(boxes);
  sparse.build(boxes);
  finest.build(boxes);
  const auto total_cells = [](const SortedGrid& g) {
    return static_cast<std::uint64_t>(g.grid().dims[0]) * static_cast<std::uint64_t>(g.grid().dims[1]);
  };
  ASSERT_LE(total_cells(dense), SortedGrid::kDenseCellsPerBox * boxes.size());  // counting sort
  for (const SortedGrid* g : {&sparse, &finest}) {
    ASSERT_GT(total_cells(*g), SortedGrid::kDenseCellsPerBox * (boxes.size() + 256));  // radix sort
  }
  ASSERT_LE(total_cells(sparse), SortedGrid::kBlockBitsPerBox * boxes.size());  // a bit a cell
  ASSERT_GT(total_cells(finest), SortedGrid::kBlockBitsPerBox * (boxes.size() + 64));  // blocks
  for (const SortedGrid* g : {&dense, &sparse, &finest}) {
    const GridMapping<2>& m = g->grid();
    for (int y = -1; y <= m.dims[1]; y += (y < 3 || y > m.dims[1] - 4) ? 1 : 7) {
      for (int x = -1; x <= m.dims[0]; x += (x < 3 || x > m.dims[0] - 4) ? 1 : 5) {
        std::vector<int> want;
        for (int i = 0; i < static_cast<int>(boxes.size()); ++i) {
          if (cell_in_range<2>(CellN<2>{x, y}, m.cell_of(boxes[i].min), m.cell_of(boxes[i].max)) &&
              x >= 0 && y >= 0 && x < m.dims[0] && y < m.dims[1]) {
            want.push_back(i);
          }
        }
        std::vector<int> got;
        for (const auto& e : g->cell_entries(CellN<2>{x, y})) got.push_back(static_cast<int>(e.id));
        ASSERT_EQ(got, want) << "cell " << x << ", " << y << " of the grid of cell size " << m.cell_size;
      }
    }
  }
  std::uniform_real_distribution<float> at(-110.0f, 110.0f), size(0.0f, 12.0f);
  int hits = 0, ray_hits = 0;
  for (int q = 0; q < 300; ++q) {
    const Vec2 lo{at(rng), at(rng)};
    const Aabb box{lo, lo + Vec2(size(rng), size(rng))};
    std::vector<int> want;
    for (int i = 0; i < static_cast<int>(boxes.size()); ++i) {
      if (overlap(box, boxes[i])) want.push_back(i);
    }
    hits += want.empty() ? 0 : 1;
    // A ray from the box's corner, up to 40 units long, and every box it meets.
    const RayN<2> ray{lo, Vec2(at(rng), at(rng)) * (40.0f / 110.0f)};
    std::vector<int> want_ray;
    for (int i = 0; i < static_cast<int>(boxes.size()); ++i) {
      if (ray_box_fraction(ray, boxes[i], 1.0f) >= 0.0f) want_ray.push_back(i);
    }
    ray_hits += want_ray.empty() ? 0 : 1;
    for (const SortedGrid* g : {&dense, &sparse, &finest}) {
      std::vector<int> got;
      g->query(box, [&](int id) {
        got.push_back(id);
        return true;
      });
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got, want) << "query " << q << ", cell size " << g->grid().cell_size;
      got.clear();
      g->ray_cast(ray, [&](int id, float f) {
        got.push_back(id);
        return f;
      });
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got, want_ray) << "ray " << q << ", cell size " << g->grid().cell_size;
    }
  }
  EXPECT_GT(hits, 100);
  EXPECT_LT(hits, 300);
  EXPECT_GT(ray_hits, 100);
  EXPECT_LT(ray_hits, 300);
}

TEST(HierarchicalGrid, MixedSizesGetTheirOwnLevels) {
  std::mt19937 rng(23);
  const auto boxes = test::mixed_size_world<3>(rng, 2000, 300.0f);
  HierarchicalGrid3 grid;
  EXPECT_EQ((pairs_of<HierarchicalGrid3, 3>(grid, boxes)), brute_pairs<3>(boxes));
  EXPECT_GE(grid.level_count(), 2);
  // Each box lives in one level and covers at most 2 cells per axis there: at most 8 cell
  // entries, a few hundred bytes per object. In level 0's cells (about 0.36 units here) one
  // 100-unit box alone would fill 2e7 of them.
  EXPECT_LT(grid.memory_bytes(), 1024 * boxes.size());
  // A uniform grid on the same data sends the 100-unit boxes to its oversized list.
  HashGrid3 hash;
  hash.build(boxes);
  EXPECT_GT(hash.oversized_count(), 50);
}

// Rays exactly along cell boundaries and through cell corners, on a lattice of boxes whose
// faces lie on those boundaries: the 3D-DDA walk must visit every cell that holds a box the
// ray touches.
// With a scheduler the pairs are found in pieces on the workers (ranges handed out from the
// end backwards by the test scheduler) and joined in order: the very list find_pairs gives on
// one thread, on worlds large enough to cut every level into several pieces.
TEST(HierarchicalGrid, PairsOnWorkersAreTheSerialListInItsOrder) {
  std::mt19937 rng(29);
  for (const int n : {3000, 40000}) {
    auto boxes = test::mixed_size_world<2>(rng, n, 8.0f * std::sqrt(static_cast<float>(n)));
    HierarchicalGrid grid;
    grid.build(boxes);
    ASSERT_GE(grid.level_count(), 2);
    PairList serial;
    grid.find_pairs(serial);
    ASSERT_GT(serial.size(), static_cast<std::size_t>(n) / 4);
    if (n <= 3000) {  // (brute force on the large world would take seconds)
      PairList sorted = serial;
      sort_pairs(sorted);
      EXPECT_EQ(sorted, brute_pairs<2>(boxes)) << n;
    }
    for (const int workers : {2, 3, 8}) {
      test::ThreadScheduler scheduler(workers);
      PairList parallel;
      grid.find_pairs(parallel, &scheduler);
      EXPECT_EQ(parallel, serial) << n << " boxes, " << workers << " workers";
    }
  }
}

/// A group of `count` boxes of half sizes in [half_lo, half_hi] for sized_world.
struct BoxGroup {
  int count;
  float half_lo;
  float half_hi;
};

/// Boxes of the groups' sizes centred uniformly in [-extent, extent]^D, shuffled.
template <int D>
test::Boxes<D> sized_world(std::mt19937& rng, float extent, std::initializer_list<BoxGroup> groups) {
  test::Boxes<D> boxes;
  for (const BoxGroup& g : groups) {
    for (int i = 0; i < g.count; ++i) {
      boxes.push_back(test::box_at<D>(test::random_vec<D>(rng, -extent, extent),
                                      test::random_vec<D>(rng, g.half_lo, g.half_hi)));
    }
  }
  std::shuffle(boxes.begin(), boxes.end(), rng);
  return boxes;
}

// A few boxes one or two levels above thousands of small ones: there the coarse boxes look up
// the fine level's cells (fewer cells visited than each small box looking up the coarse
// level). The same pairs as brute force, in 2D and 3D, and the same list on the workers.
template <int D>
void check_few_coarse_boxes(std::uint32_t seed) {
  std::mt19937 rng(seed);
  const auto boxes = sized_world<D>(rng, D == 2 ? 40.0f : 12.0f, {{3000, 0.25f, 0.5f}, {12, 1.2f, 2.0f}, {2, 5.0f, 8.0f}});
  HierarchicalGridN<D> grid;
  grid.build(boxes);
  ASSERT_GE(grid.level_count(), 3);
  PairList serial;
  grid.find_pairs(serial);
  PairList sorted = serial;
  sort_pairs(sorted);
  const PairList want = brute_pairs<D>(boxes);
  ASSERT_GT(want.size(), 1000u);
  EXPECT_EQ(sorted, want);
  for (const int workers : {2, 3}) {
    test::ThreadScheduler scheduler(workers);
    PairList parallel;
    grid.find_pairs(parallel, &scheduler);
    EXPECT_EQ(parallel, serial) << workers << " workers";
  }
}

TEST(HierarchicalGrid, FewCoarseBoxesLookUpTheFineLevel) {
  check_few_coarse_boxes<2>(37);
  check_few_coarse_boxes<3>(41);
}

// A level far smaller than the next coarser one (kMinorityRatio: under an eighth of its boxes)
// joins it: a ray would walk its fine, nearly empty cells for few boxes. 3000 boxes of 0.5-1
// units, 100 of 3-5 and either 100 boxes of 0.04-0.08 units (they join the 3000) or 1000.
// Pairs as brute force; a ray gives the boxes it meets, and, clipped at each hit, the nearest.
template <int D>
void check_minority_level(std::uint32_t seed) {
  for (const int tiny : {100, 1000}) {
    std::mt19937 rng(seed);
    const float extent = D == 2 ? 40.0f : 12.0f;
    // (the 100 coarser boxes keep their level: a ray walks few of its cells)
    const auto boxes = sized_world<D>(rng, extent, {{3000, 0.25f, 0.5f}, {tiny, 0.02f, 0.04f}, {100, 1.5f, 2.5f}});
    HierarchicalGridN<D> grid;
    EXPECT_EQ((pairs_of<HierarchicalGridN<D>, D>(grid, boxes)), brute_pairs<D>(boxes)) << tiny;
    EXPECT_EQ(grid.level_count(), tiny == 100 ? 2 : 3) << tiny;
    int hits = 0;
    for (int q = 0; q < 200; ++q) {
      const RayN<D> ray{test::random_vec<D>(rng, -extent, extent), test::random_vec<D>(rng, -2.0f * extent, 2.0f * extent)};
      std::vector<int> want, got;
      float nearest = 2.0f;
      for (int i = 0; i < static_cast<int>(boxes.size()); ++i) {
        const float f = ray_box_fraction(ray, boxes[static_cast<std::size_t>(i)], 1.0f);
        if (f < 0.0f) continue;
        want.push_back(i);
        nearest = std::min(nearest, f);
      }
      grid.ray_cast(ray, [&](int id, float f) {
        got.push_back(id);
        return f;
      });
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got, want) << tiny << " ray " << q;
      // Clipped at each hit: no box met only beyond the clip so far is given.
      float clipped = 2.0f, clip = 1.0f;
      int beyond = 0;
      grid.ray_cast(ray, [&](int id, float) {
        const float f = ray_box_fraction(ray, boxes[static_cast<std::size_t>(id)], 1.0f);
        beyond += f > clip ? 1 : 0;
        clipped = std::min(clipped, f);
        clip = std::min(clip, f);
        return f;
      });
      if (!want.empty()) EXPECT_EQ(clipped, nearest) << tiny << " ray " << q;
      EXPECT_EQ(beyond, 0) << tiny << " ray " << q;
      hits += want.empty() ? 0 : 1;
    }
    EXPECT_GT(hits, 50) << tiny;
  }
}

TEST(HierarchicalGrid, MinorityLevelJoinsTheNextCoarser) {
  check_minority_level<2>(43);
  check_minority_level<3>(47);
}

TEST(GridRayCast, AlongCellBoundariesAndThroughCorners) {
  std::mt19937 rng(31);
  const auto boxes = test::touching_world<2>(rng, 300, 10);
  HashGrid hash({.cell_size = 1.0f});
  SortedGrid sorted({.cell_size = 1.0f});
  HierarchicalGrid levels({.base_cell_size = 1.0f});
  BruteForce brute;
  hash.build(boxes);
  sorted.build(boxes);
  levels.build(boxes);
  brute.build(boxes);
  int hits = 0;
  for (int i = -10; i <= 10; ++i) {
    const float c = static_cast<float>(i);
    const Ray rays[] = {
        {{-15.0f, c}, {30.0f, 0.0f}},   // along a horizontal boundary
        {{c, 15.0f}, {0.0f, -30.0f}},   // along a vertical boundary, downwards
        {{-12.0f, c - 12.0f}, {24.0f, 24.0f}},  // diagonal through lattice corners
        {{12.0f, c + 12.0f}, {-24.0f, -24.0f}}, // the same, backwards
        {{c, -12.0f}, {-24.0f, 24.0f}},         // the other diagonal
    };
    for (const Ray& ray : rays) {
      std::vector<int> want, got_hash, got_sorted, got_levels;
      brute.ray_cast(ray, [&](int id, float f) { want.push_back(id); return f; });
      hash.ray_cast(ray, [&](int id, float f) { got_hash.push_back(id); return f; });
      sorted.ray_cast(ray, [&](int id, float f) { got_sorted.push_back(id); return f; });
      levels.ray_cast(ray, [&](int id, float f) { got_levels.push_back(id); return f; });
      for (auto* got : {&got_hash, &got_sorted, &got_levels}) {
        std::sort(got->begin(), got->end());
        EXPECT_EQ(*got, want) << "ray from " << ray.origin.x << "," << ray.origin.y;
      }
      hits += !want.empty();
    }
  }
  EXPECT_GT(hits, 60);
}

// Quarter turns, mirror images and integer translations (up to 1e4) map boxes with integer
// corners to such boxes exactly: the pair set must be the same under every one of them.
TEST(BroadPhases, PairsInvariantUnderRigidMotionsOfTheLattice) {
  std::mt19937 rng(41);
  const auto boxes = test::touching_world<3>(rng, 400, 6);
  const PairList want = brute_pairs<3>(boxes);
  ASSERT_GT(want.size(), 100u);
  std::uniform_int_distribution<int> shift(-10000, 10000);
  for (int trial = 0; trial < 6; ++trial) {
    int perm[3] = {0, 1, 2};
    std::shuffle(perm, perm + 3, rng);
    const float sign[3] = {rng() % 2 ? 1.0f : -1.0f, rng() % 2 ? 1.0f : -1.0f,
                           rng() % 2 ? 1.0f : -1.0f};
    const Vec3 t{static_cast<float>(shift(rng)), static_cast<float>(shift(rng)),
                 static_cast<float>(shift(rng))};
    std::vector<Aabb3> moved;
    for (const Aabb3& b : boxes) {
      Aabb3 m;
      for (int k = 0; k < 3; ++k) {
        const float lo = sign[k] * b.min[perm[k]], hi = sign[k] * b.max[perm[k]];
        m.min[k] = std::min(lo, hi) + t[k];
        m.max[k] = std::max(lo, hi) + t[k];
      }
      moved.push_back(m);
    }
    for (const std::string_view name : broadphase_names()) {
      EXPECT_EQ(find_pairs(name, std::span<const Aabb3>(moved)), want) << name << " " << trial;
    }
  }
}

// LooseGrid: boxes exactly one cell wide sit on cell boundaries, span two cells and pair with
// neighbours through the half-neighbourhood scan only; wider boxes become big.
TEST(LooseGrid, TouchingOnCellBoundariesAndBigBoxes) {
  std::mt19937 rng(8);
  const auto boxes2 = test::touching_world<2>(rng, 400, 12);
  const auto boxes3 = test::touching_world<3>(rng, 400, 6);
  const PairList want2 = brute_pairs<2>(boxes2), want3 = brute_pairs<3>(boxes3);
  ASSERT_GT(want2.size(), 200u);
  ASSERT_GT(want3.size(), 100u);
  int big = 0;
  for (const float cell : {0.25f, 0.5f, 1.0f, 2.0f, 3.0f}) {
    LooseGrid g2({.cell_size = cell});
    LooseGrid3 g3({.cell_size = cell});
    EXPECT_EQ((pairs_of<LooseGrid, 2>(g2, boxes2)), want2) << cell;
    EXPECT_EQ((pairs_of<LooseGrid3, 3>(g3, boxes3)), want3) << cell;
    big += g2.big_count() + g3.big_count();
  }
  EXPECT_GT(big, 100);  // the small cells really made big boxes
}

// Mixed sizes give big boxes (against small ones by cell range, against each other by a sweep);
// clusters far apart make a sparse grid whose cells are widened to the budget.
TEST(LooseGrid, MixedSizesSparseClustersAndFarWorlds) {
  std::mt19937 rng(31);
  const auto check = [&]<int D>(const test::Boxes<D>& boxes, const char* what) {
    LooseGridN<D> grid;
    EXPECT_EQ((pairs_of<LooseGridN<D>, D>(grid, boxes)), brute_pairs<D>(boxes)) << what << D;
    std::uint64_t cells = 1;
    for (int k = 0; k < D; ++k) cells *= static_cast<std::uint64_t>(grid.grid().dims[k] + 2);
    EXPECT_LE(cells, LooseGridN<D>::kCellsPerBox * boxes.size() + LooseGridN<D>::kMinCells) << what;
    return grid.big_count();
  };
  EXPECT_GT(check(test::mixed_size_world<2>(rng, 800, 200.0f), "mixed"), 20);
  EXPECT_GT(check(test::mixed_size_world<3>(rng, 800, 80.0f), "mixed"), 20);
  EXPECT_GE(check(test::huge_object_world<2>(rng, 500, 40.0f), "huge"), 4);
  EXPECT_GE(check(test::huge_object_world<3>(rng, 500, 16.0f), "huge"), 4);
  for (const float offset : {0.0f, -5.0e5f, 1.0e6f}) {
    // Two dense clusters 1e5 apart (cells widened) near `offset`.
    test::Boxes<2> two2 = test::uniform_world<2>(rng, 300, 10.0f, 0.2f, 1.0f, offset);
    test::Boxes<3> two3 = test::uniform_world<3>(rng, 300, 4.0f, 0.2f, 1.0f, offset);
    for (const auto& b : test::uniform_world<2>(rng, 300, 10.0f, 0.2f, 1.0f, offset + 1.0e5f)) two2.push_back(b);
    for (const auto& b : test::uniform_world<3>(rng, 300, 4.0f, 0.2f, 1.0f, offset + 1.0e5f)) two3.push_back(b);
    check(two2, "clusters");
    check(two3, "clusters");
    check(test::uniform_world<2>(rng, 600, 30.0f, 0.1f, 1.5f, offset), "uniform");
    check(test::uniform_world<3>(rng, 600, 12.0f, 0.1f, 1.5f, offset), "uniform");
  }
}

// The cell quantile decides how many boxes are big (kept out of the cells): at 0.05 most are,
// at 1 none but the outliers. Queries and rays find the big ones by a search along x over them
// sorted by min x (the widest among them bounding how far back a box can start): every box a
// query box, a point or a segment meets, once, and the nearest entry of a clipped ray, as brute
// force finds them, with one box as wide as the world among them.
TEST(LooseGrid, BigBoxesAreFoundByQueriesAndRaysAtEveryCellQuantile) {
  const auto check = []<int D>(float quantile) -> int {
    std::mt19937 rng(47 + D);
    test::Boxes<D> boxes = test::uniform_world<D>(rng, 500, D == 2 ? 20.0f : 8.0f, 0.1f, 1.5f);
    for (const AabbN<D>& b : test::mixed_size_world<D>(rng, 100, 60.0f)) boxes.push_back(b);
    AabbN<D> world = boxes[0];
    for (const AabbN<D>& b : boxes) world = merge(world, b);
    boxes[17] = {world.min, world.min + VecN<D>(1.0f)};
    boxes[17].max[0] = world.max[0];  // as wide as the world
    LooseGridN<D> grid({.cell_quantile = quantile});
    grid.build(boxes);
    BruteForceN<D> brute;
    brute.build(boxes);
    const auto sorted = [](std::vector<int> ids) {
      std::sort(ids.begin(), ids.end());
      return ids;
    };
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const auto random_point = [&] {
      VecN<D> p;
      for (int k = 0; k < D; ++k) p[k] = world.min[k] + (world.max[k] - world.min[k]) * (1.2f * unit(rng) - 0.1f);
      return p;
    };
    for (int q = 0; q < 300; ++q) {
      const VecN<D> a = q % 2 == 0 ? boxes[rng() % boxes.size()].center() : random_point();
      const VecN<D> b = random_point();
      const AabbN<D> box{glm::min(a, a + 0.05f * (b - a)), glm::max(a, a + 0.05f * (b - a))};
      std::vector<int> got, want;
      grid.query(box, [&](int id) { got.push_back(id); return true; });
      brute.query(box, [&](int id) { want.push_back(id); return true; });
      EXPECT_EQ(sorted(got), sorted(want)) << D << " q " << quantile << " query " << q;
      got.clear(), want.clear();
      grid.query_point(a, [&](int id) { got.push_back(id); return true; });
      brute.query_point(a, [&](int id) { want.push_back(id); return true; });
      EXPECT_EQ(sorted(got), sorted(want)) << D << " q " << quantile << " point " << q;
      const RayN<D> ray{a, (q % 3 == 0 ? 0.1f : 1.0f) * (b - a)};
      got.clear(), want.clear();
      grid.ray_cast(ray, [&](int id, float f) { got.push_back(id); return f; });
      brute.ray_cast(ray, [&](int id, float f) { want.push_back(id); return f; });
      EXPECT_EQ(sorted(got), sorted(want)) << D << " q " << quantile << " ray " << q;
      float best = 2.0f, want_best = 2.0f;
      const auto clip = [&](float& out) {
        return [&](int id, float limit) {
          const float f = ray_box_fraction(ray, boxes[std::size_t(id)], limit);
          if (f >= 0.0f && f < out) out = f;
          return f >= 0.0f ? f : limit;
        };
      };
      grid.ray_cast(ray, clip(best));
      brute.ray_cast(ray, clip(want_best));
      EXPECT_EQ(best, want_best) << D << " q " << quantile << " closest ray " << q;
    }
    return grid.big_count();
  };
  // (The counts of big boxes: the search over them is exercised at every quantile but 1.)
  EXPECT_GT(check.operator()<2>(0.05f), 200);
  EXPECT_GE(check.operator()<3>(0.05f), 2);
  EXPECT_GT(check.operator()<2>(0.5f), 50);
  EXPECT_GE(check.operator()<3>(0.5f), 2);
  EXPECT_GE(check.operator()<2>(0.9f), 2);
  EXPECT_GE(check.operator()<3>(0.9f), 2);
  EXPECT_EQ(check.operator()<2>(1.0f), 0);
  EXPECT_EQ(check.operator()<3>(1.0f), 0);
}

// Large grids are counting-sorted band by band; one_step_bits = 0 and small bands force that
// path on small worlds and must give the same pairs (and order) as the one-step sort.
TEST(LooseGrid, BandedSortMatchesTheOneStepSort) {
  std::mt19937 rng(77);
  const auto check = [&]<int D>(const test::Boxes<D>& boxes, const char* what) {
    LooseGridN<D> one_step({.one_step_bits = 31});
    one_step.build(boxes);
    PairList want;
    one_step.find_pairs(want);
    for (const int bits : {0, 3, 6}) {
      LooseGridN<D> banded({.one_step_bits = 0, .band_bits = bits});
      banded.build(boxes);
      PairList got;
      banded.find_pairs(got);
      EXPECT_EQ(got, want) << what << " D=" << D << " band_bits=" << bits;
    }
    sort_pairs(want);
    EXPECT_EQ(want, brute_pairs<D>(boxes)) << what << " D=" << D;
  };
  check(test::uniform_world<2>(rng, 800, 30.0f, 0.1f, 1.5f), "uniform");
  check(test::uniform_world<3>(rng, 800, 12.0f, 0.1f, 1.5f), "uniform");
  check(test::clustered_world<2>(rng, 600, 50.0f), "clustered");
  check(test::clustered_world<3>(rng, 600, 50.0f), "clustered");
  check(test::mixed_size_world<2>(rng, 600, 200.0f), "mixed");
  check(test::mixed_size_world<3>(rng, 600, 80.0f), "mixed");
  check(test::touching_world<2>(rng, 400, 12), "touching");
  check(test::touching_world<3>(rng, 400, 6), "touching");
}

// update on a grid sorted band by band writes each record straight into a region sized from
// the band's count in the last call: frames of small motions (every band within its slack),
// then half the boxes crowding into a corner of the grid (their bands outgrow the slack, the
// count is taken again), then spreading back. Every frame against brute force, and the pairs
// (with their order) as a fresh build sorted the same way.
TEST(LooseGrid, UpdateByBandsMatchesBruteForceAsBandsGrowAndShrink) {
  std::mt19937 rng(61);
  const auto check = [&]<int D>() {
    const float extent = D == 2 ? 30.0f : 10.0f;
    auto world = test::moving_world<D>(rng, test::uniform_world<D>(rng, 2500, extent, 0.1f, 0.6f), extent, 0.15f);
    const typename LooseGridN<D>::Options options{.cell_size = 1.5f, .one_step_bits = 0, .band_bits = 6};
    LooseGridN<D> grid(options);
    grid.build(world.boxes);
    const auto frame = [&](const std::string& what) {
      grid.update(world.boxes);
      PairList got;
      grid.find_pairs(got);
      LooseGridN<D> fresh(options);
      fresh.build(world.boxes);
      PairList again;
      fresh.find_pairs(again);
      PairList sorted = got;
      sort_pairs(sorted);
      EXPECT_EQ(sorted, brute_pairs<D>(world.boxes)) << D << " " << what;
      if (grid.grid().bounds.min == fresh.grid().bounds.min && grid.grid().bounds.max == fresh.grid().bounds.max) {
        EXPECT_EQ(got, again) << D << " " << what;
      }
    };
    for (int f = 0; f < 5; ++f) {
      world.step();
      frame("small motions " + std::to_string(f));
    }
    const test::Boxes<D> before = world.boxes;
    for (std::size_t i = 0; i < world.boxes.size(); i += 2) {
      world.boxes[i] = test::box_at<D>(VecN<D>(-extent + 2.0f) + test::random_vec<D>(rng, 0.0f, 3.0f), VecN<D>(0.3f));
    }
    frame("crowded corner");
    world.boxes = before;
    frame("spread again");
    world.step();
    frame("small motion after");
  };
  check.template operator()<2>();
  check.template operator()<3>();
}

// On grids sorted band by band, each band's records and boxes are written a line of
// kLineSlots (8) slots at a time, the partly filled line last, and each band's cell starts
// are counted apart and copied out. Bands of every size modulo 8 (small worlds of 1 to 120
// boxes, bands of 4 and 32 cells), at build (regions counted) and over updates (regions
// sized from the last call): pairs against brute force each frame, and at build in the order
// of the one-step sort.
TEST(LooseGrid, BandedLinesOfEverySizeMatchBruteForce) {
  std::mt19937 rng(93);
  const auto check = [&]<int D>() {
    for (int n = 1; n <= 120; n += (n < 20 ? 1 : 7)) {
      const float extent = D == 2 ? 0.6f * std::sqrt(static_cast<float>(n)) + 2.0f
                                  : 0.8f * std::cbrt(static_cast<float>(n)) + 2.0f;
      auto world = test::moving_world<D>(rng, test::uniform_world<D>(rng, n, extent, 0.1f, 0.8f), extent, 0.2f);
      LooseGridN<D> one_step({.cell_size = 1.0f, .one_step_bits = 31});
      one_step.build(world.boxes);
      PairList want;
      one_step.find_pairs(want);
      for (const int bits : {2, 5}) {
        LooseGridN<D> banded({.cell_size = 1.0f, .one_step_bits = 0, .band_bits = bits});
        banded.build(world.boxes);
        PairList got;
        banded.find_pairs(got);
        EXPECT_EQ(got, want) << "D=" << D << " n=" << n << " band_bits=" << bits;
        auto moving = world;
        // The combined calls on a twin: the same pairs and order, found band by band.
        LooseGridN<D> fused({.cell_size = 1.0f, .one_step_bits = 0, .band_bits = bits});
        PairList fused_pairs;
        fused.build_and_find_pairs(world.boxes, fused_pairs);
        EXPECT_EQ(fused_pairs, want) << "D=" << D << " n=" << n << " band_bits=" << bits;
        for (int f = 0; f < 4; ++f) {
          moving.step();
          banded.update(moving.boxes);
          banded.find_pairs(got);
          fused.update_and_find_pairs(moving.boxes, fused_pairs);
          EXPECT_EQ(fused_pairs, got) << "D=" << D << " n=" << n << " band_bits=" << bits << " frame " << f;
          sort_pairs(got);
          EXPECT_EQ(got, brute_pairs<D>(moving.boxes)) << "D=" << D << " n=" << n << " band_bits=" << bits << " frame " << f;
        }
      }
    }
  };
  check.template operator()<2>();
  check.template operator()<3>();
}

// build_and_find_pairs / update_and_find_pairs on grids sorted band by band find each band's
// pairs right after sorting it, from copies in cache; an entry whose neighbourhood reaches into
// the next band (its row above in 2D, its plane above in 3D, often several small bands away)
// waits for it, and big boxes and outliers (kept beside the grid) are tested band by band.
// Against a twin grid with the same options calling build / update then find_pairs: the same
// pairs in the same order, every frame, and brute force; the grid left queryable (find_pairs
// and a box query again give the same); the pair list handed in holding stale pairs.
TEST(LooseGrid, CombinedCallsMatchTheSeparateCallsAcrossBands) {
  std::mt19937 rng(31);
  const auto check = [&]<int D>(const test::Boxes<D>& start, float extent, const char* what) {
    for (const int bits : {0, 2, 3, 5, 7, 19}) {
      const typename LooseGridN<D>::Options options{.one_step_bits = bits == 19 ? 31 : 0, .band_bits = bits};
      LooseGridN<D> fused(options), twin(options);
      auto world = test::moving_world<D>(rng, start, extent, 0.3f);
      PairList got(std::size_t{5000} * (bits % 3), BroadPair{-7, -7});  // stale pairs, 0 to 10000
      PairList want;
      std::size_t crossing = 0;  // pairs of boxes in different bands
      for (int f = 0; f < 4; ++f) {
        const std::string at = std::string(what) + " D=" + std::to_string(D) + " band_bits=" +
                               std::to_string(bits) + " frame " + std::to_string(f);
        if (f == 0) {
          fused.build_and_find_pairs(world.boxes, got);
          twin.build(world.boxes);
        } else {
          fused.update_and_find_pairs(world.boxes, got);
          twin.update(world.boxes);
        }
        twin.find_pairs(want);
        ASSERT_EQ(got, want) << at;
        PairList again;
        fused.find_pairs(again);
        EXPECT_EQ(again, want) << at;
        PairList sorted = got;
        sort_pairs(sorted);
        EXPECT_EQ(sorted, brute_pairs<D>(world.boxes)) << at;
        EXPECT_EQ(fused.big_count(), twin.big_count()) << at;
        const AabbN<D> probe = test::box_at<D>(test::random_vec<D>(rng, -extent, extent), VecN<D>(0.2f * extent));
        std::vector<int> found, expected;
        fused.query(probe, [&](int id) { found.push_back(id); return true; });
        twin.query(probe, [&](int id) { expected.push_back(id); return true; });
        EXPECT_EQ(found, expected) << at;
        // Bands of the pairs' boxes (by min-corner cell key, with the border).
        const GridMapping<D>& grid = fused.grid();
        const auto band = [&](const AabbN<D>& box) {
          if (!contains(grid.bounds, box)) return -1;
          const CellN<D> c = grid.cell_of(box.min);
          std::int64_t key = 0;
          for (int k = D - 1; k >= 0; --k) key = key * (grid.dims[k] + 2) + c[k] + 1;
          return static_cast<int>(key >> bits);
        };
        for (const BroadPair& p : got) crossing += band(world.boxes[p.first]) != band(world.boxes[p.second]);
        world.step();
      }
      if (bits < 19) EXPECT_GT(crossing, 0u) << what << " D=" << D << " band_bits=" << bits;
    }
  };
  check(test::uniform_world<2>(rng, 900, 30.0f, 0.1f, 1.5f), 30.0f, "uniform");
  check(test::uniform_world<3>(rng, 900, 12.0f, 0.1f, 1.5f), 12.0f, "uniform");
  check(test::clustered_world<2>(rng, 700, 50.0f), 50.0f, "clustered");
  check(test::clustered_world<3>(rng, 700, 50.0f), 50.0f, "clustered");
  check(test::mixed_size_world<2>(rng, 700, 200.0f), 200.0f, "mixed");
  check(test::mixed_size_world<3>(rng, 700, 80.0f), 80.0f, "mixed");
  check(test::huge_object_world<2>(rng, 700, 40.0f), 40.0f, "huge");
  check(test::huge_object_world<3>(rng, 700, 15.0f), 15.0f, "huge");
  check(test::touching_world<2>(rng, 500, 12), 12.0f, "touching");
  check(test::touching_world<3>(rng, 500, 6), 6.0f, "touching");
}

// Outliers: boxes beyond the grid laid over a sample of the boxes are kept with the big ones
// (update keeps its grid while few leave it); the combined calls test them band by band. Some
// straddle the grid's edge, so they meet boxes inside. Same pairs and order as the separate
// calls, and brute force.
TEST(LooseGrid, CombinedCallsKeepOutliersBesideTheGrid) {
  std::mt19937 rng(47);
  const auto check = [&]<int D>() {
    constexpr int n = 2 * kCellSizeSamples;  // sampled: the grid does not cover every box
    const float extent = D == 2 ? 40.0f : 12.0f;
    test::Boxes<D> boxes = test::uniform_world<D>(rng, n, extent, 0.1f, 0.5f);
    for (int m = 0; m < 12; ++m) {
      const int i = 2 * (m * 37 % (n / 2)) + 1;
      const float out = m % 3 == 0 ? extent + 0.3f : extent + 3.0f + static_cast<float>(m) * 2.0f;
      boxes[i] = test::box_at<D>(VecN<D>(out) + test::random_vec<D>(rng, -0.2f, 0.2f), VecN<D>(m % 3 == 0 ? 1.5f : 0.5f));
    }
    for (const int bits : {1, 4, 6}) {
      const typename LooseGridN<D>::Options options{.cell_size = 2.0f, .one_step_bits = 0, .band_bits = bits};
      LooseGridN<D> fused(options), twin(options);
      auto world = test::moving_world<D>(rng, boxes, extent, 0.05f);
      PairList got, want;
      for (int f = 0; f < 3; ++f) {
        if (f == 0) {
          fused.build_and_find_pairs(world.boxes, got);
          twin.build(world.boxes);
        } else {
          fused.update_and_find_pairs(world.boxes, got);
          twin.update(world.boxes);
        }
        twin.find_pairs(want);
        EXPECT_GE(fused.big_count(), 12) << D << " band_bits=" << bits << " frame " << f;
        ASSERT_EQ(got, want) << D << " band_bits=" << bits << " frame " << f;
        std::size_t with_outlier = 0;
        for (const BroadPair& p : got) {
          with_outlier += !contains(fused.grid().bounds, world.boxes[p.first]) ||
                          !contains(fused.grid().bounds, world.boxes[p.second]);
        }
        EXPECT_GT(with_outlier, 0u) << D;
        sort_pairs(got);
        EXPECT_EQ(got, brute_pairs<D>(world.boxes)) << D << " band_bits=" << bits << " frame " << f;
        world.step();
      }
    }
  };
  check.template operator()<2>();
  check.template operator()<3>();
}

// A bad box makes the combined calls throw, leaving the grid and the pair list empty; the next
// call works again.
TEST(LooseGrid, CombinedCallsRejectBadBoxesAndAreLeftEmpty) {
  std::mt19937 rng(53);
  test::Boxes<2> boxes = test::uniform_world<2>(rng, 3000, 30.0f, 0.1f, 0.6f);
  LooseGrid grid({.one_step_bits = 0, .band_bits = 4});
  PairList pairs;
  grid.build_and_find_pairs(boxes, pairs);
  EXPECT_FALSE(pairs.empty());
  test::Boxes<2> bad = boxes;
  bad[1234].max.y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(grid.update_and_find_pairs(bad, pairs), InvalidInput);
  EXPECT_TRUE(pairs.empty());
  EXPECT_EQ(grid.size(), 0);
  PairList none;
  grid.find_pairs(none);
  EXPECT_TRUE(none.empty());
  bad[1234] = boxes[1234];
  bad[77].min.x = std::numeric_limits<float>::infinity();
  EXPECT_THROW(grid.build_and_find_pairs(bad, pairs), InvalidInput);
  EXPECT_TRUE(pairs.empty());
  grid.update_and_find_pairs(boxes, pairs);
  sort_pairs(pairs);
  EXPECT_EQ(pairs, brute_pairs<2>(boxes));
}

// A band holding more than kBandCopy boxes is sorted without copying its boxes out: 140000
// boxes on a grid of two bands, the first with more than half the cells. Pairs (and their
// order) as the one-step sort, and the set as a plain sweep along x.
TEST(LooseGrid, CrowdedBandMatchesTheOneStepSort) {
  std::mt19937 rng(88);
  constexpr int n = 140000;
  const test::Boxes<2> boxes = test::uniform_world<2>(rng, n, 180.0f, 0.1f, 0.5f);
  LooseGrid one_step({.one_step_bits = 31});
  one_step.build(boxes);
  PairList want;
  one_step.find_pairs(want);
  // Bands of 2^bits cells, bits the largest with two bands; the boxes of the first band.
  const CellN<2> dims = one_step.grid().dims;
  const auto cells = static_cast<std::uint32_t>((dims.x + 2) * (dims.y + 2));
  const int bits = std::bit_width(cells - 1) - 1;
  int in_first_band = 0;
  for (const Aabb& b : boxes) {
    const CellN<2> c = one_step.grid().cell_of(b.min);
    const auto key = static_cast<std::uint32_t>((c.y + 1) * (dims.x + 2) + c.x + 1);
    in_first_band += (key >> bits) == 0;
  }
  ASSERT_GT(in_first_band, static_cast<int>(LooseGrid::kBandCopy));
  LooseGrid banded({.one_step_bits = 0, .band_bits = bits});
  banded.build(boxes);
  PairList got;
  banded.find_pairs(got);
  EXPECT_EQ(got, want);
  PairList fused;
  LooseGrid({.one_step_bits = 0, .band_bits = bits}).build_and_find_pairs(boxes, fused);
  EXPECT_EQ(fused, want);
  // The sweep: boxes by min.x, each against those starting before its max.x.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return boxes[a].min.x < boxes[b].min.x; });
  PairList swept;
  for (int i = 0; i < n; ++i) {
    const Aabb& a = boxes[order[i]];
    for (int j = i + 1; j < n && boxes[order[j]].min.x <= a.max.x; ++j) {
      if (overlap(a, boxes[order[j]])) swept.emplace_back(std::min(order[i], order[j]), std::max(order[i], order[j]));
    }
  }
  sort_pairs(swept);
  sort_pairs(got);
  EXPECT_EQ(got, swept);
  EXPECT_GT(swept.size(), static_cast<std::size_t>(n / 4));
}

// Cells holding many boxes: the neighbour runs are longer than one four-wide test (the pair
// pass's overflow loop) and the box counts are not multiples of four (the copy's tail). Pairs
// and box queries against brute force.
TEST(LooseGrid, CrowdedCellsAndEveryCountModFour) {
  std::mt19937 rng(12);
  const auto check = [&]<int D>(int n) {
    // Boxes of 0.3 to 1 in [0, 4]^D with unit cells: about n / 4^D boxes per cell.
    const test::Boxes<D> boxes = test::uniform_world<D>(rng, n, 2.0f, 0.15f, 0.5f, 2.0f);
    LooseGridN<D> grid({.cell_size = 1.0f});
    const PairList want = brute_pairs<D>(boxes);
    ASSERT_GT(want.size(), static_cast<std::size_t>(2 * n));  // crowded: runs of 9 or more
    EXPECT_EQ((pairs_of<LooseGridN<D>, D>(grid, boxes)), want) << D << " " << n;
    for (int q = 0; q < 20; ++q) {
      const AabbN<D> box = test::box_at<D>(test::random_vec<D>(rng, 0.0f, 4.0f),
                                           test::random_vec<D>(rng, 0.0f, 1.0f));
      std::vector<int> got, brute;
      grid.query(box, [&](int id) { got.push_back(id); return true; });
      for (int i = 0; i < n; ++i) {
        if (overlap(box, boxes[i])) brute.push_back(i);
      }
      std::sort(got.begin(), got.end());
      EXPECT_EQ(got, brute) << D << " " << n << " query " << q;
    }
  };
  for (const int n : {200, 201, 202, 203}) {
    check.template operator()<2>(n);
    check.template operator()<3>(n);
  }
}

// Worlds of 1 to 9 boxes in a few unit cells: every entry is in the scalar tails of the
// four-wide passes (the copy, the 3D crossing classes), and boxes of neighbouring layers meet.
TEST(LooseGrid, TinyWorldsRunTheScalarTails) {
  std::mt19937 rng(21);
  const auto check = [&]<int D>() {
    std::size_t pairs = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const int n = 1 + trial % 9;
      const test::Boxes<D> boxes = test::uniform_world<D>(rng, n, 1.0f, 0.1f, 0.5f, 1.5f);
      LooseGridN<D> grid({.cell_size = 1.0f});
      const PairList want = brute_pairs<D>(boxes);
      EXPECT_EQ((pairs_of<LooseGridN<D>, D>(grid, boxes)), want) << D << " trial " << trial;
      pairs += want.size();
    }
    EXPECT_GT(pairs, 300u);
  };
  check.template operator()<2>();
  check.template operator()<3>();
}

// The bounds pass reads boxes in SIMD lanes, two 2D boxes per step: a bad coordinate must be
// caught in every lane, at even and odd positions and in the tail, and the bounds must be exact.
TEST(GridMapping, CheckedBoundsCatchesEveryCoordinateOfEveryBox) {
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(),
                       std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity()};
  const auto check = [&]<int D>() {
    std::mt19937 rng(3 + D);
    for (const int n : {1, 2, 3, 4, 5}) {
      const test::Boxes<D> good = test::uniform_world<D>(rng, n, 10.0f, 0.0f, 2.0f, -3.0f);
      const AabbN<D> bounds = checked_bounds_of<D>(good);
      EXPECT_EQ(bounds.min, bounds_of<D>(good).min);
      EXPECT_EQ(bounds.max, bounds_of<D>(good).max);
      for (int i = 0; i < n; ++i) {
        for (int a = 0; a < 2 * D; ++a) {
          for (const float value : bad) {
            test::Boxes<D> boxes = good;
            (a < D ? boxes[i].min[a] : boxes[i].max[a - D]) = value;
            EXPECT_THROW((void)checked_bounds_of<D>(boxes), InvalidInput) << D << n << i << a;
          }
          // min > max on axis a % D
          test::Boxes<D> boxes = good;
          boxes[i].min[a % D] = boxes[i].max[a % D] + 1.0f;
          EXPECT_THROW((void)checked_bounds_of<D>(boxes), InvalidInput) << D << n << i << a;
        }
      }
    }
  };
  check.template operator()<2>();
  check.template operator()<3>();
}

// build lays the grid over the bounds of the boxes it samples for the cell size: with n = 2 *
// kCellSizeSamples boxes the sample is every even index (sample_largest_sides' even stride), so
// boxes moved away at odd indices lie outside that grid. A few are kept with the big boxes; many
// make the grid be laid again over the exact bounds. Pairs and queries against brute force.
TEST(LooseGrid, BoxesOutsideTheSampledGridAreKeptWithTheBigOnes) {
  std::mt19937 rng(41);
  const auto check = [&]<int D>(int moved, bool kept) {
    constexpr int n = 2 * kCellSizeSamples;
    const float extent = D == 2 ? 40.0f : 12.0f;
    test::Boxes<D> boxes = test::uniform_world<D>(rng, n, extent, 0.1f, 0.5f);
    // Odd boxes moved beyond the grid, in clumps of three that overlap each other; the first
    // straddles the edge of the sampled bounds, so it also meets boxes inside.
    for (int m = 0; m < moved; ++m) {
      const int i = 2 * (m * 37 % (n / 2)) + 1;
      const float out = m == 0 ? extent + 0.3f : extent + 3.0f + static_cast<float>(m / 3) * 2.0f;
      boxes[i] = test::box_at<D>(VecN<D>(out) + test::random_vec<D>(rng, -0.2f, 0.2f), VecN<D>(m == 0 ? 1.5f : 0.5f));
    }
    LooseGridN<D> grid({.cell_size = 2.0f});  // no box spans more than two cells: big = outlier
    const PairList want = brute_pairs<D>(boxes);
    EXPECT_EQ((pairs_of<LooseGridN<D>, D>(grid, boxes)), want) << D << " moved " << moved;
    int outside = 0;
    for (const AabbN<D>& b : boxes) outside += !contains(grid.grid().bounds, b);
    if (kept) {
      // The moved boxes and any other unsampled box beyond the sample's grown bounds.
      EXPECT_EQ(grid.big_count(), outside) << D;
      EXPECT_GE(outside, moved) << D;
      EXPECT_LE(outside, n / 1024 + 8) << D;
    } else {
      EXPECT_EQ(grid.big_count(), 0) << D;
      EXPECT_EQ(outside, 0) << D;
    }
    // Queries reach the outliers: a box and a ray through the far clumps, a point in one.
    const AabbN<D> far{VecN<D>(extent + 1.0f), VecN<D>(extent + 1000.0f)};
    std::vector<int> got, expected;
    grid.query(far, [&](int id) { got.push_back(id); return true; });
    for (int i = 0; i < n; ++i) {
      if (overlap(far, boxes[i])) expected.push_back(i);
    }
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected) << D;
    EXPECT_GE(expected.size(), static_cast<std::size_t>(moved - 1)) << D;
    got.clear();
    expected.clear();
    const RayN<D> ray{VecN<D>(0.0f), VecN<D>(extent + 1000.0f)};
    grid.ray_cast(ray, [&](int id, float f) { got.push_back(id); return f; });
    for (int i = 0; i < n; ++i) {
      if (ray_box_fraction(ray, boxes[i], 1.0f) >= 0.0f) expected.push_back(i);
    }
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected) << D;
    EXPECT_GT(expected.size(), 2u) << D;
  };
  for (const bool three_d : {false, true}) {
    // 10 <= outlier_limit (n / 1024 + 8 = 16); 600 > it.
    if (three_d) {
      check.template operator()<3>(10, true);
      check.template operator()<3>(600, false);
    } else {
      check.template operator()<2>(10, true);
      check.template operator()<2>(600, false);
    }
  }
}

// update keeps its grid while the boxes stay in it: boxes taken out of the grid one per frame
// are kept with the big ones (the grid stays), then too many leave it and the grid is laid
// again over the bounds grown by the update margin, which the next frames' small motions stay
// inside. Every frame against brute force.
TEST(LooseGrid, UpdateKeepsItsGridUntilTooManyBoxesLeaveIt) {
  std::mt19937 rng(43);
  const auto check = [&]<int D>() {
    const float extent = D == 2 ? 30.0f : 10.0f;
    test::Boxes<D> boxes = test::uniform_world<D>(rng, 3000, extent, 0.1f, 0.6f);
    LooseGridN<D> grid({.cell_size = 1.5f});  // no box spans more than two cells: big = outlier
    grid.build(boxes);
    ASSERT_EQ(grid.big_count(), 0);
    const auto frame = [&](const char* what, int outliers, bool same_grid) {
      const AabbN<D> before = grid.grid().bounds;
      grid.update(boxes);
      const AabbN<D> after = grid.grid().bounds;
      EXPECT_EQ(after.min == before.min && after.max == before.max, same_grid) << D << " " << what;
      EXPECT_EQ(grid.big_count(), outliers) << D << " " << what;
      int outside = 0;
      for (const AabbN<D>& b : boxes) outside += !contains(after, b);
      EXPECT_EQ(outside, outliers) << D << " " << what;
      PairList got;
      grid.find_pairs(got);
      sort_pairs(got);
      EXPECT_EQ(got, brute_pairs<D>(boxes)) << D << " " << what;
    };
    // One more box per frame next to the last one beyond the grid (3000 / 1024 + 8 = 10 allowed).
    for (int m = 0; m < 6; ++m) {
      boxes[100 * m] = test::box_at<D>(VecN<D>(extent + 2.0f + 0.5f * static_cast<float>(m)), VecN<D>(0.4f));
      frame("a few outside", m + 1, true);
    }
    for (int m = 6; m < 60; ++m) {
      boxes[100 * m % 2999] = test::box_at<D>(VecN<D>(extent + 2.0f + 0.5f * static_cast<float>(m)), VecN<D>(0.4f));
    }
    frame("many outside", 0, false);
    // Every box moves by up to 0.2 (less than a cell, the margin's least part): the grid stays.
    for (int f = 0; f < 3; ++f) {
      for (AabbN<D>& b : boxes) {
        const VecN<D> step = test::random_vec<D>(rng, -0.2f, 0.2f);
        b.min += step;
        b.max += step;
      }
      frame("small motions", 0, true);
    }
  };
  check.template operator()<2>();
  check.template operator()<3>();
}

// update validates each box in the key pass (no bounds pass while it keeps its grid): a bad
// coordinate inside the grid's bounds, in every lane, throws naming the box and leaves the grid
// empty; the next good update works.
TEST(LooseGrid, UpdateRejectsBadBoxesInsideItsGridAndIsLeftEmpty) {
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(),
                       std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity()};
  const auto check = [&]<int D>() {
    std::mt19937 rng(3 + D);
    const test::Boxes<D> good = test::uniform_world<D>(rng, 7, 3.0f, 0.2f, 1.0f);
    LooseGridN<D> grid;
    grid.build(good);
    const PairList want = brute_pairs<D>(good);
    ASSERT_FALSE(want.empty());
    for (int i = 0; i < 7; ++i) {
      for (int a = 0; a < 2 * D; ++a) {
        for (int v = 0; v < 4; ++v) {
          test::Boxes<D> boxes = good;
          if (v < 3) {
            (a < D ? boxes[i].min[a] : boxes[i].max[a - D]) = bad[v];
          } else {
            // min > max on axis a % D, both inside the grid's bounds
            std::swap(boxes[i].min[a % D], boxes[i].max[a % D]);
          }
          try {
            grid.update(boxes);
            ADD_FAILURE() << "accepted: D " << D << " box " << i << " coordinate " << a << " case " << v;
          } catch (const InvalidInput& e) {
            EXPECT_NE(std::string(e.what()).find("box " + std::to_string(i)), std::string::npos) << e.what();
          }
          EXPECT_EQ(grid.size(), 0);
          PairList none;
          grid.find_pairs(none);
          EXPECT_TRUE(none.empty());
          int hits = 0;
          grid.query(bounds_of<D>(good), [&](int) { ++hits; return true; });
          EXPECT_EQ(hits, 0);
          grid.update(good);
          EXPECT_EQ((pairs_of_update<LooseGridN<D>, D>(grid, good)), want);
        }
      }
    }
  };
  check.template operator()<2>();
  check.template operator()<3>();
}

// Frames allocate nothing once the grid has seen the world: each call of every kind (build,
// update, the combined calls; one-step and banded sorts) over the same cycle of moving poses
// of a world with big boxes, counted by the test's operator new. Regressions: the big-small
// pairs of the banded combined calls were put in order by std::stable_sort, which allocates a
// buffer per call; and a build reserved its band regions to the exact size, so that a
// slightly larger count reallocated the records and staged boxes (8-24 MB at a million boxes).
TEST(LooseGrid, FramesAllocateNothingOnceWarm) {
  std::mt19937 rng(71);
  const auto check = [&]<int D>(const test::Boxes<D>& start, float extent, const char* what) {
    // 12 poses forward, then back: the second time round the cycle meets nothing new.
    auto world = test::moving_world<D>(rng, start, extent, 0.2f);
    std::vector<test::Boxes<D>> poses;
    for (int f = 0; f < 12; ++f, world.step()) poses.push_back(world.boxes);
    for (int f = 11; f >= 0; --f) poses.push_back(poses[static_cast<std::size_t>(f)]);
    for (const bool banded : {false, true}) {
      for (int call = 0; call < 4; ++call) {
        const typename LooseGridN<D>::Options options{.one_step_bits = banded ? 0 : 31, .band_bits = 4};
        LooseGridN<D> grid(options);
        PairList pairs;
        const auto frame = [&](const test::Boxes<D>& boxes) {
          switch (call) {
            case 0: grid.build(boxes); grid.find_pairs(pairs); break;
            case 1: grid.update(boxes); grid.find_pairs(pairs); break;
            case 2: grid.build_and_find_pairs(boxes, pairs); break;
            default: grid.update_and_find_pairs(boxes, pairs); break;
          }
        };
        for (int round = 0; round < 2; ++round) {
          for (const auto& boxes : poses) frame(boxes);
        }
        ASSERT_GT(grid.big_count(), 0) << what;
        test::AllocationCounter counter;
        for (const auto& boxes : poses) frame(boxes);
        EXPECT_EQ(counter.count(), 0u) << what << " D=" << D << " banded=" << banded << " call=" << call;
        EXPECT_FALSE(pairs.empty()) << what;
      }
    }
  };
  check(test::mixed_size_world<2>(rng, 2000, 200.0f), 200.0f, "mixed");
  check(test::mixed_size_world<3>(rng, 2000, 60.0f), 60.0f, "mixed");
  check(test::huge_object_world<2>(rng, 2000, 40.0f), 40.0f, "huge");
  check(test::huge_object_world<3>(rng, 2000, 15.0f), 15.0f, "huge");
}

// A build reserves room for the band regions of any distribution of its boxes over the bands
// (each band's region is rounded up to whole buffers), not just for the last one's: the same
// number of boxes spread over more bands must not reallocate the records and staged boxes.
// Regression: the exact size was reserved, so a build whose bands took a few more slots than
// any before reallocated both (8-24 MB at a million boxes, every few frames).
TEST(LooseGrid, BuildReservesRoomForAnyBandCounts) {
  std::mt19937 rng(73);
  const auto check = [&]<int D>(float extent) {
    // The same grid for both worlds: the same box sizes (cell size) and the same corners
    // (bounds); the boxes of `half` fill half of the bands, those of `all` every band.
    const auto world = [&](float lo_x) {
      test::Boxes<D> boxes;
      for (int i = 0; i < 3000; ++i) {
        VecN<D> c = test::random_vec<D>(rng, -extent, extent);
        c.x = test::uniform_f(rng, lo_x, extent);
        boxes.push_back(test::box_at<D>(c, VecN<D>(0.5f)));
      }
      for (int corner = 0; corner < (1 << D); ++corner) {
        VecN<D> c;
        for (int k = 0; k < D; ++k) c[k] = (corner >> k) & 1 ? extent : -extent;
        boxes.push_back(test::box_at<D>(c, VecN<D>(0.5f)));
      }
      return boxes;
    };
    const test::Boxes<D> half = world(0.0f), all = world(-extent);
    LooseGridN<D> grid(typename LooseGridN<D>::Options{.one_step_bits = 0, .band_bits = 3});
    grid.build(half);
    grid.build(half);
    const GridMapping<D> mapping = grid.grid();
    test::AllocationCounter counter;
    grid.build(all);
    EXPECT_EQ(counter.count(), 0u) << "D=" << D;
    EXPECT_EQ(grid.grid().dims, mapping.dims) << "D=" << D;  // the same grid, more bands used
    PairList pairs;
    grid.find_pairs(pairs);
    sort_pairs(pairs);
    EXPECT_EQ(pairs, brute_pairs<D>(all)) << "D=" << D;
  };
  check.operator()<2>(60.0f);
  check.operator()<3>(15.0f);
}

TEST(LooseGrid, RejectsBadOptions) {
  EXPECT_THROW(LooseGrid({.band_bits = -1}), InvalidInput);
  EXPECT_THROW(LooseGrid({.band_bits = 32}), InvalidInput);
  EXPECT_THROW(LooseGrid({.one_step_bits = -1}), InvalidInput);
  EXPECT_THROW(LooseGrid({.one_step_bits = 32}), InvalidInput);
  EXPECT_THROW(LooseGrid({.cell_size = -1.0f}), InvalidInput);
  EXPECT_THROW(LooseGrid({.cell_size = std::nanf("")}), InvalidInput);
}

TEST(DynamicTree, SmallMotionsReinsertFewLeavesAndTheTreeStaysShallow) {
  std::mt19937 rng(51);
  auto world = test::moving_world<2>(rng, test::uniform_world<2>(rng, 4000, 100.0f, 0.5f, 1.0f),
                                     100.0f, 0.05f);
  DynamicTree tree;
  tree.build(world.boxes);
  EXPECT_LE(tree.height(), 2 * 12 + 4);  // about 2 log2(4000)
  int reinserted = 0;
  for (int frame = 0; frame < 40; ++frame) {
    world.step();
    tree.update(world.boxes);
    reinserted += tree.reinserted_count();
  }
  EXPECT_LT(reinserted, 40 * 4000 / 5);
  EXPECT_GT(reinserted, 0);
  EXPECT_LE(tree.height(), 2 * 12 + 6);
  PairList pairs;
  tree.find_pairs(pairs);
  sort_pairs(pairs);
  EXPECT_EQ(pairs, brute_pairs<2>(world.boxes));
}

}  // namespace
}  // namespace collide
