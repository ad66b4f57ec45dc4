#pragma once
// Replays every file of a folder through a fuzz target's check: how the tests keep the inputs a
// fuzzer found a defect with (fuzz/regressions/<kind>/) and its seeds passing.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace collide::test {

/// Runs `check` (input bytes -> "" when the contract holds, else what broke) on every regular
/// file of `folder` whose name does not start with '.', expecting "" for each; returns how many
/// files were checked.
template <class Check>
int replay_files(const std::filesystem::path& folder, Check&& check) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (!entry.is_regular_file() || entry.path().filename().string().starts_with(".")) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string input{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_EQ(check(input), "") << entry.path();
    ++files;
  }
  return files;
}

}  // namespace collide::test
