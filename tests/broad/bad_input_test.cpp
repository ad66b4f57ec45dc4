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
