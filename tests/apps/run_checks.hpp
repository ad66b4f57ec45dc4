#pragma once
// Checks both runs share (2D run_world, 3D run_world3d): the state hash is a function of the
// options that choose what happens, not of how the world finds it; a summary says tunnelled 0,
// its hash and its events; an events file is well-formed JSON Lines.

#include "run.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <regex>
#include <set>
#include <string>

namespace collide::test {

using cli::RunOptions;

/// Expects `run(options).state_hash` to be the same on a second run, with each broad phase of
/// `broad_phases` and with the fixed early-out order, and to differ with another seed.
template <class Run>
void expect_hash_independent_of_choices(Run&& run, const RunOptions& options,
                                        std::initializer_list<WorldBroadPhase> broad_phases) {
  const auto hash = run(options).state_hash;
  EXPECT_EQ(run(options).state_hash, hash);
  for (const WorldBroadPhase bp : broad_phases) {
    RunOptions o = options;
    o.broad_phase = bp;
    EXPECT_EQ(run(o).state_hash, hash) << to_string(bp);
  }
  RunOptions fixed = options;
  fixed.adaptive_early_out = false;
  EXPECT_EQ(run(fixed).state_hash, hash);
  RunOptions other_seed = options;
  other_seed.seed = options.seed + 1;
  EXPECT_NE(run(other_seed).state_hash, hash);
}

/// What a run's summary says that later checks need.
struct RunSummary {
  std::string hash;   ///< the state hash, 16 hex digits
  long written = -1;  ///< events written to the events file
};

/// Expects the summary `output` to say tunnelled 0 and to carry a state hash and the count of
/// events written; returns them (empty / -1 where missing, after a failure).
inline RunSummary expect_clean_summary(const std::string& output) {
  RunSummary s;
  std::smatch m;
  if (std::regex_search(output, m, std::regex(R"(tunnelled\s+(\d+) bodies)"))) {
    EXPECT_EQ(m[1].str(), "0") << output;
  } else {
    ADD_FAILURE() << "no tunnelled line:\n" << output;
  }
  if (std::regex_search(output, m, std::regex(R"(state hash\s+([0-9a-f]{16}))"))) {
    s.hash = m[1].str();
  } else {
    ADD_FAILURE() << "no state hash:\n" << output;
  }
  if (std::regex_search(output, m, std::regex(R"((\d+) written to)"))) {
    s.written = std::stol(m[1].str());
  } else {
    ADD_FAILURE() << "no events count:\n" << output;
  }
  return s;
}

/// Expects `path` to hold one JSON event per line: type begin, persist or end, every pair's
/// begin before its persist and end, a unit normal and contact points of `dims` coordinates,
/// A a body. Returns the number of lines.
inline long expect_valid_events_file(const std::string& path, int dims) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::string line;
  long lines = 0;
  std::set<std::string> open;
  while (std::getline(in, line)) {
    const nlohmann::json e = nlohmann::json::parse(line);
    ++lines;
    const std::string key = e["a"].dump() + e["b"].dump();
    const std::string type = e["type"];
    EXPECT_TRUE(type == "begin" || type == "persist" || type == "end") << line;
    if (type == "begin") {
      EXPECT_TRUE(open.insert(key).second) << line;
    } else {
      EXPECT_EQ(open.count(key), 1u) << "without a begin: " << line;
      if (type == "end") open.erase(key);
    }
    EXPECT_TRUE(e["a"].contains("body")) << line;
    EXPECT_EQ(e["normal"].size(), static_cast<std::size_t>(dims)) << line;
    double n2 = 0.0;
    for (const auto& c : e["normal"]) n2 += static_cast<double>(c) * static_cast<double>(c);
    EXPECT_NEAR(n2, 1.0, 1e-3) << line;
    for (const auto& p : e["points"]) EXPECT_EQ(p["point"].size(), static_cast<std::size_t>(dims)) << line;
  }
  return lines;
}

}  // namespace collide::test
