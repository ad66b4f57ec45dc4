// Bad options and bad arguments: every structure rejects them with collide::InvalidInput whose
// message names the field or argument, so a user can tell which one to fix.

#include <collide/broad/dynamic_tree.hpp>
#include <collide/broad/hash_grid.hpp>
#include <collide/broad/hierarchical_grid.hpp>
#include <collide/broad/loose_grid.hpp>
#include <collide/broad/sorted_grid.hpp>
#include <collide/broad/temporal_broad_phase.hpp>
#include <collide/core/error.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace collide {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

/// One call that must be rejected, and the name its message must contain.
struct Rejected {
  std::string field;
  std::function<void()> call;
};

void expect_named(const std::vector<Rejected>& cases) {
  for (const Rejected& c : cases) {
    try {
      c.call();
      ADD_FAILURE() << c.field << ": accepted";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(c.field == "margin" ? "margin:" : c.field), std::string::npos)
          << "message does not name " << c.field << ": " << e.what();
    }
  }
}

template <int D>
std::vector<Rejected> bad_options() {
  using Hash = HashGridN<D>;
  using Sorted = SortedGridN<D>;
  using Hier = HierarchicalGridN<D>;
  using Tree = DynamicTreeN<D>;
  using Loose = LooseGridN<D>;
  using Temporal = TemporalBroadPhaseN<D>;
  std::vector<Rejected> cases;
  for (const float bad : {-1.0f, kNaN, kInf}) {
    cases.push_back({"cell_size", [=] { (void)Hash({.cell_size = bad}); }});
    cases.push_back({"cell_size", [=] { (void)Sorted({.cell_size = bad}); }});
    cases.push_back({"cell_size", [=] { (void)Loose({.cell_size = bad}); }});
    cases.push_back({"base_cell_size", [=] { (void)Hier({.base_cell_size = bad}); }});
    cases.push_back({"margin", [=] { (void)Tree({.margin = bad}); }});
    cases.push_back({"margin_fraction", [=] { (void)Tree({.margin_fraction = bad}); }});
    cases.push_back({"horizon", [=] { (void)Temporal({.horizon = static_cast<double>(bad)}); }});
  }
  for (const int bad : {0, -3}) {
    cases.push_back({"max_cells_per_box", [=] { (void)Hash({.max_cells_per_box = bad}); }});
    cases.push_back({"max_cells_per_box", [=] { (void)Sorted({.max_cells_per_box = bad}); }});
  }
  for (const float bad : {0.0f, -0.5f, 1.01f, kNaN, kInf}) {
    cases.push_back({"cell_quantile", [=] { (void)Loose({.cell_quantile = bad}); }});
  }
  for (const int bad : {-1, 32}) {
    cases.push_back({"one_step_bits", [=] { (void)Loose({.one_step_bits = bad}); }});
    cases.push_back({"band_bits", [=] { (void)Loose({.band_bits = bad}); }});
  }
  return cases;
}

TEST(BadOptions, EveryRejectedOptionIsNamed2D) { expect_named(bad_options<2>()); }
TEST(BadOptions, EveryRejectedOptionIsNamed3D) { expect_named(bad_options<3>()); }

// The edges of the valid ranges are accepted (0 chooses from the data).
TEST(BadOptions, TheEdgesOfTheRangesAreAccepted) {
  EXPECT_NO_THROW((void)HashGrid({.cell_size = 0.0f, .max_cells_per_box = 1}));
  EXPECT_NO_THROW((void)SortedGrid3({.cell_size = 0.0f, .max_cells_per_box = 1}));
  EXPECT_NO_THROW((void)HierarchicalGrid({.base_cell_size = 0.0f}));
  EXPECT_NO_THROW((void)DynamicTree3({.margin = 0.0f, .margin_fraction = 0.0f}));
  EXPECT_NO_THROW((void)LooseGrid({.cell_size = 0.0f, .one_step_bits = 0, .band_bits = 31}));
  EXPECT_NO_THROW((void)LooseGrid3({.cell_quantile = 1.0f}));
  EXPECT_NO_THROW((void)TemporalBroadPhase({.horizon = 0.0}));
}

// reserve(-1, ...) used to reach std::vector::reserve as a huge size_t: std::length_error,
// which names nothing.
TEST(HashGrid, ReserveRejectsNegativeCountsNamingTheArgument) {
  HashGrid grid;
  HashGrid3 grid3;
  expect_named({
      {"boxes", [&] { grid.reserve(-1, 10); }},
      {"cell_entries", [&] { grid.reserve(10, -1); }},
      {"cell_entries", [&] { grid3.reserve(0, -100); }},
  });
  EXPECT_NO_THROW(grid.reserve(0, 0));
  EXPECT_EQ(grid.size(), 0);
}

}  // namespace
}  // namespace collide
