// Every input the query fuzzer found a defect with (fuzz/regressions/query_line/), and its
// seeds, replayed through the fuzz target's own check (fuzz/query_line_check.hpp).

#include "query_line_check.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace collide::cli {
namespace {

namespace fs = std::filesystem;

/// Runs the check on every file of `folder` (names starting with '.' are not inputs).
int replay(const fs::path& folder) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file() || entry.path().filename().string().starts_with(".")) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string input{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_EQ(fuzz::check_query_line(input), "") << entry.path();
    ++files;
  }
  return files;
}

TEST(QueryFuzzRegressions, EveryFoundInputAndSeedPassesTheFuzzCheck) {
  replay(fs::path(COLLIDE_FUZZ_DIR) / "regressions" / "query_line");
  EXPECT_GE(replay(fs::path(COLLIDE_FUZZ_DIR) / "seeds" / "query_line"), 8);
}

}  // namespace
}  // namespace collide::cli
