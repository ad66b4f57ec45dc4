// Every input the scene fuzzer found a defect with (fuzz/regressions/scene_json/), its seeds and
// the example scenes, replayed through the fuzz target's own check (fuzz/scene_json_check.hpp).

#include "scene_json_check.hpp"

#include "support/replay_files.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace collide {
namespace {

namespace fs = std::filesystem;

int replay(const fs::path& folder) {
  return test::replay_files(folder,
                            [](const std::string& input) { return fuzz::check_scene_json(input); });
}

TEST(SceneFuzzRegressions, EveryFoundInputAndSeedPassesTheFuzzCheck) {
  replay(fs::path(COLLIDE_FUZZ_DIR) / "regressions" / "scene_json");
  EXPECT_GE(replay(fs::path(COLLIDE_FUZZ_DIR) / "seeds" / "scene_json"), 3);
  EXPECT_EQ(replay(fs::path(COLLIDE_EXAMPLES_DIR) / "scenes"), 2);
}

}  // namespace
}  // namespace collide
