// Every input the scene fuzzer found a defect with (fuzz/regressions/scene_json/), its seeds and
// the example scenes, replayed through the fuzz target's own check (fuzz/scene_json_check.hpp).

#include "scene_json_check.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace collide {
namespace {

namespace fs = std::filesystem;

/// Runs the check on every file of `folder` (names starting with '.' are not inputs).
int replay(const fs::path& folder) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file() || entry.path().filename().string().starts_with(".")) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string input{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_EQ(fuzz::check_scene_json(input), "") << entry.path();
    ++files;
  }
  return files;
}

TEST(SceneFuzzRegressions, EveryFoundInputAndSeedPassesTheFuzzCheck) {
  replay(fs::path(COLLIDE_FUZZ_DIR) / "regressions" / "scene_json");
  EXPECT_GE(replay(fs::path(COLLIDE_FUZZ_DIR) / "seeds" / "scene_json"), 3);
  EXPECT_EQ(replay(fs::path(COLLIDE_EXAMPLES_DIR) / "scenes"), 2);
}

}  // namespace
}  // namespace collide
