// Every input the query fuzzer found a defect with (fuzz/regressions/query_line/), and its
// seeds, replayed through the fuzz target's own check (fuzz/query_line_check.hpp).

#include "query_line_check.hpp"

#include "support/replay_files.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace collide::cli {
namespace {

namespace fs = std::filesystem;

int replay(const fs::path& folder) {
  return test::replay_files(folder,
                            [](const std::string& input) { return fuzz::check_query_line(input); });
}

TEST(QueryFuzzRegressions, EveryFoundInputAndSeedPassesTheFuzzCheck) {
  replay(fs::path(COLLIDE_FUZZ_DIR) / "regressions" / "query_line");
  EXPECT_GE(replay(fs::path(COLLIDE_FUZZ_DIR) / "seeds" / "query_line"), 8);
}

}  // namespace
}  // namespace collide::cli
