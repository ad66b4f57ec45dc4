// Every input the Tiled fuzzers found a defect with (fuzz/regressions/tiled_*/) and their seeds,
// replayed through the fuzz targets' own check (fuzz/tiled_check.hpp), and the shared real maps,
// tilesets and templates through it too.

#include "tiled_check.hpp"

#include "support/replay_files.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace collide {
namespace {

namespace fs = std::filesystem;

struct Kind {
  const char* folder;
  fuzz::TiledInput input;
};

constexpr Kind kKinds[] = {{"tiled_tmx", fuzz::TiledInput::tmx},
                           {"tiled_tmj", fuzz::TiledInput::tmj},
                           {"tiled_tsx", fuzz::TiledInput::tileset},
                           {"tiled_tx", fuzz::TiledInput::templ}};

/// Replays every file of `folder`; `rejected` counts those the loader refused (cleanly).
int replay(const fs::path& folder, fuzz::TiledInput input, const fs::path& scratch, int& rejected) {
  return test::replay_files(folder, [&](const std::string& bytes) {
    bool accepted = false;
    std::string problem = fuzz::check_tiled(input, bytes, scratch, &accepted);
    rejected += accepted ? 0 : 1;
    return problem;
  });
}

TEST(TiledFuzzRegressions, EveryFoundInputAndSeedPassesTheFuzzCheck) {
  const fs::path scratch = fs::temp_directory_path() / "collide_tiled_fuzz_replay";
  for (const Kind& kind : kKinds) {
    SCOPED_TRACE(kind.folder);
    int rejected = 0;
    replay(fs::path(COLLIDE_FUZZ_DIR) / "regressions" / kind.folder, kind.input, scratch, rejected);
    rejected = 0;
    EXPECT_GE(replay(fs::path(COLLIDE_FUZZ_DIR) / "seeds" / kind.folder, kind.input, scratch, rejected), 2);
    EXPECT_EQ(rejected, 0) << "every seed is a map the loader accepts";
  }
  fs::remove_all(scratch);
}

}  // namespace
}  // namespace collide
