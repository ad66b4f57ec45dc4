// The `collide query` protocol: answers checked against analytic geometry, every rejection in the
// spec's error list answered with an error naming the field, and the stream going on after it.

#include "query.hpp"

#include <collide/broad/registry.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <random>
#include <vector>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

namespace collide::cli {
namespace {

using nlohmann::json;

json ask(const std::string& line) {
  const std::string reply = answer_query_line(line);
  EXPECT_EQ(reply.find('\n'), std::string::npos);
  return json::parse(reply);
}

std::string error_of(const std::string& line) {
  const json j = ask(line);
  EXPECT_TRUE(j.contains("error")) << line << " -> " << j.dump();
  return j.value("error", "");
}

TEST(Query, OverlapAndDistanceOfTwoCirclesAreAnalytic) {
  const json o = ask(R"({"id": 7, "op": "overlap", "a": {"type": "circle", "radius": 1},
      "b": {"type": "circle", "radius": 1}, "xb": {"p": [1.5, 0]}})");
  EXPECT_EQ(o["id"], 7);
  EXPECT_TRUE(o["overlap"].get<bool>());
  const json d = ask(R"({"id": "d", "op": "distance", "a": {"type": "circle", "radius": 1},
      "b": {"type": "box", "half": [1, 1]}, "xb": {"p": [5, 0], "angle": 0}})");
  EXPECT_EQ(d["id"], "d");
  EXPECT_NEAR(d["distance"].get<double>(), 3.0, 1e-5);
  EXPECT_NEAR(d["pa"][0].get<double>(), 1.0, 1e-5);
  EXPECT_NEAR(d["pb"][0].get<double>(), 4.0, 1e-5);
}

TEST(Query, ContactOfStackedBoxesHasTwoPointsAndUpwardNormal) {
  const json c = ask(R"({"id": [1, 2], "op": "contact", "a": {"type": "box", "half": [2, 1]},
      "b": {"type": "box", "half": [1, 1]}, "xb": {"p": [0, 1.9]}})");
  EXPECT_EQ(c["id"], json::array({1, 2}));
  ASSERT_TRUE(c["touching"].get<bool>()) << c.dump();
  EXPECT_NEAR(c["normal"][0].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(c["normal"][1].get<double>(), 1.0, 1e-6);
  EXPECT_NEAR(c["depth"].get<double>(), 0.1, 1e-5);
  ASSERT_EQ(c["points"].size(), 2u);
  const json apart = ask(R"({"op": "contact", "a": {"type": "circle", "radius": 1},
      "b": {"type": "circle", "radius": 1}, "xb": {"p": [3, 0]}})");
  EXPECT_FALSE(apart["touching"].get<bool>());
  EXPECT_FALSE(apart.contains("normal"));
  EXPECT_TRUE(apart["id"].is_null());
}

TEST(Query, RaycastAndClosestPointOnARotatedBox) {
  const json r = ask(R"({"op": "raycast", "shape": {"type": "box", "half": [1, 1]},
      "x": {"p": [10, 0]}, "origin": [0, 0], "translation": [20, 0]})");
  ASSERT_TRUE(r["hit"].get<bool>());
  EXPECT_NEAR(r["fraction"].get<double>(), 9.0 / 20.0, 1e-6);
  EXPECT_NEAR(r["normal"][0].get<double>(), -1.0, 1e-6);
  const json inside = ask(R"({"op": "raycast", "shape": {"type": "circle", "radius": 1},
      "origin": [0, 0], "translation": [5, 0]})");
  EXPECT_FALSE(inside["hit"].get<bool>());

  const json p = ask(R"({"op": "closest_point", "shape": {"type": "polygon",
      "vertices": [[0, 0], [4, 0], [0, 3]]}, "point": [5, -1]})");
  EXPECT_FALSE(p["inside"].get<bool>());
  EXPECT_EQ(p["feature"], "vertex 1");
  EXPECT_NEAR(p["distance"].get<double>(), std::sqrt(2.0), 1e-5);
  const json q = ask(R"({"op": "closest_point", "shape": {"type": "polygon",
      "vertices": [[0, 0], [4, 0], [0, 3]]}, "point": [1, 0.5]})");
  EXPECT_TRUE(q["inside"].get<bool>());
  EXPECT_EQ(q["feature"], "edge 0");
  EXPECT_NEAR(q["distance"].get<double>(), -0.5, 1e-5);
}

TEST(Query, NumbersRoundTripAsFloatsWithShortDigits) {
  const std::string reply = answer_query_line(
      R"({"op": "closest_point", "shape": {"type": "circle", "radius": 0.1}, "point": [0.3, 0]})");
  EXPECT_NE(reply.find("\"distance\":0.2"), std::string::npos) << reply;
}

TEST(Query, EveryRejectionInTheSpecNamesItsField) {
  EXPECT_NE(error_of("{not json").find("not valid JSON"), std::string::npos);
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "circle", "radius": 1e999}})").find("a.radius"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "explode"})").find("unknown op"), std::string::npos);
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "blob"}, "b": {"type": "circle", "radius": 1}})")
                .find("a.type"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "overlap", "b": {"type": "circle", "radius": 1}})").find("a: missing"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "raycast", "shape": {"type": "circle", "radius": 1}, "origin": [0, 0, 1, 2], "translation": [1, 0]})")
                .find("origin"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "circle", "radius": -1}, "b": {"type": "circle", "radius": 1}})")
                .find("a.radius"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "circle", "radius": 1e39}, "b": {"type": "circle", "radius": 1}})")
                .find("finite"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "polygon", "vertices": [[0,0],[0,1],[1,0]]}, "b": {"type": "circle", "radius": 1}})")
                .find("clockwise"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "polygon", "vertices": [[0,0],[1,0],[1,0]]}, "b": {"type": "circle", "radius": 1}})")
                .find("a:"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "polygon", "vertices": [[0,0],[2,0],[1,0.2],[2,1],[0,1]]}, "b": {"type": "circle", "radius": 1}})")
                .find("vertex 2"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "sphere", "center": [0,0,0], "radius": 1}, "b": {"type": "circle", "radius": 1}})")
                .find("3D"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "circle", "radius": 1}, "xa": {"p": [0, "x"]}, "b": {"type": "circle", "radius": 1}})")
                .find("xa.p[1]"),
            std::string::npos);
}

// A number beyond double range (1e400) is a non-finite number like any other: the answer echoes
// the id and names the field, though JSON parsing alone rejects the whole line.
TEST(Query, NumbersBeyondDoubleRangeAreNamedWithTheIdEchoed) {
  const json a = ask(R"({"id": 5, "op": "overlap", "a": {"type": "circle", "radius": 1e400},
      "b": {"type": "circle", "radius": 1}})");
  EXPECT_EQ(a["id"], 5);
  EXPECT_EQ(a.value("error", ""), "a.radius: not a finite float (1e400 is beyond double range)");
  // Negative, in an array, and with a string that looks like such a number left alone.
  const json b = ask(R"({"id": "-1e400 \" 2e999", "op": "pairs",
      "boxes": [[0, 0, 1, 1], [0, 0, -1E+400, 1]]})");
  EXPECT_EQ(b["id"], "-1e400 \" 2e999");
  EXPECT_EQ(b.value("error", ""), "boxes[1][2]: not a finite float (-1E+400 is beyond double range)");
  // Numbers that underflow to 0 are ordinary; a syntax error is still a syntax error.
  EXPECT_FALSE(ask(R"({"op": "overlap", "a": {"type": "circle", "radius": 1e-400},
      "b": {"type": "circle", "radius": 1}})").contains("error"));
  EXPECT_NE(error_of(R"({"id": 1, "op": "overlap", "a": 1e400,)").find("not valid JSON"),
            std::string::npos);
}

TEST(Query, StreamAnswersEveryLineInOrderAndSkipsBlankLines) {
  std::istringstream in(
      "{\"id\": 1, \"op\": \"overlap\", \"a\": {\"type\": \"circle\", \"radius\": 1}, "
      "\"b\": {\"type\": \"circle\", \"radius\": 1}}\n"
      "\n"
      "garbage\n"
      "{\"id\": 3, \"op\": \"distance\", \"a\": {\"type\": \"circle\", \"radius\": 1}, "
      "\"b\": {\"type\": \"circle\", \"radius\": 1}, \"xb\": {\"p\": [3, 0]}}\n");
  std::ostringstream out;
  EXPECT_EQ(answer_query_stream(in, out), 3u);
  std::istringstream lines(out.str());
  std::string l1, l2, l3;
  std::getline(lines, l1);
  std::getline(lines, l2);
  std::getline(lines, l3);
  EXPECT_EQ(json::parse(l1)["id"], 1);
  EXPECT_TRUE(json::parse(l2).contains("error"));
  EXPECT_EQ(json::parse(l3)["id"], 3);
  EXPECT_NEAR(json::parse(l3)["distance"].get<double>(), 1.0, 1e-6);
}

TEST(Query, TheShippedExampleRunsThroughTheRealBinaryWithoutErrors) {
  const std::string cmd =
      std::string(COLLIDE_CLI_PATH) + " query " + COLLIDE_EXAMPLES_DIR + "/queries.jsonl";
  FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), static_cast<int>(buf.size()), pipe) != nullptr) output += buf.data();
  EXPECT_EQ(pclose(pipe), 0);
  std::ifstream questions(std::string(COLLIDE_EXAMPLES_DIR) + "/queries.jsonl");
  std::istringstream answers(output);
  std::string question, reply;
  int count = 0;
  while (std::getline(questions, question)) {
    if (question.find_first_not_of(" \t\r") == std::string::npos) continue;
    ASSERT_TRUE(std::getline(answers, reply)) << "no answer for " << question;
    const json q = json::parse(question);
    const json a = json::parse(reply);
    EXPECT_EQ(a["id"], q["id"]);
    EXPECT_EQ(a.contains("error"), q.value("expect_error", false)) << reply;
    ++count;
  }
  EXPECT_GE(count, 8);
}

}  // namespace
}  // namespace collide::cli

namespace collide::cli {
namespace {

TEST(QueryPairs, EveryBroadPhaseGivesTheBruteForcePairsIn2DAnd3D) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> pos(-10.0f, 10.0f);
  std::uniform_real_distribution<float> size(0.1f, 6.0f);
  for (const int dim : {2, 3}) {
    json boxes = json::array();
    std::vector<std::vector<float>> raw;
    for (int i = 0; i < 60; ++i) {
      std::vector<float> lo, hi;
      for (int k = 0; k < dim; ++k) {
        lo.push_back(pos(rng));
        hi.push_back(lo.back() + size(rng));
      }
      std::vector<float> b = lo;
      b.insert(b.end(), hi.begin(), hi.end());
      raw.push_back(b);
      boxes.push_back(b);
    }
    json expected = json::array();
    for (size_t i = 0; i < raw.size(); ++i) {
      for (size_t j = i + 1; j < raw.size(); ++j) {
        bool touch = true;
        for (int k = 0; k < dim; ++k) {
          touch = touch && raw[i][k] <= raw[j][k + dim] && raw[j][k] <= raw[i][k + dim];
        }
        if (touch) expected.push_back(json::array({i, j}));
      }
    }
    ASSERT_GT(expected.size(), 20u);  // dense enough that pairs and non-pairs both occur
    ASSERT_LT(expected.size(), raw.size() * (raw.size() - 1) / 4);
    // Every name the registry knows (what `collide query --help` lists), and the default.
    std::vector<std::string> names(1, "");
    for (const std::string_view name : broadphase_names()) names.emplace_back(name);
    ASSERT_GE(names.size(), 9u);
    for (const std::string& name : names) {
      json q = {{"id", name}, {"op", "pairs"}, {"boxes", boxes}};
      if (!name.empty()) q["broadphase"] = name;
      const json a = ask(q.dump());
      EXPECT_EQ(a["id"], name);
      EXPECT_EQ(a["pairs"], expected) << "broadphase '" << name << "' in " << dim << "D";
    }
  }
  // An unknown name: said once of "broadphase", with the valid names to pick from.
  const std::string unknown =
      error_of(R"({"op": "pairs", "boxes": [[0, 0, 1, 1]], "broadphase": "octree"})");
  EXPECT_EQ(unknown.rfind("broadphase: unknown name \"octree\" (valid: ", 0), 0u) << unknown;
  EXPECT_EQ(unknown.find("broadphase: broadphase"), std::string::npos) << unknown;
  for (const std::string_view name : broadphase_names()) {
    EXPECT_NE(unknown.find(name), std::string::npos) << name << " not listed: " << unknown;
  }
  EXPECT_NE(error_of(R"({"op": "pairs", "boxes": [[0, 0, 1, 1], [0, 0, 1]]})").find("boxes[1]"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"op": "pairs", "boxes": [[0, 0, 1, 1], [2, 0, 1, 1]]})").find("box 1"),
            std::string::npos);
  EXPECT_NE(query_ops_help().find("sweep_and_prune"), std::string::npos);
}

}  // namespace
}  // namespace collide::cli

namespace collide::cli {
namespace {

TEST(QueryToi, FirstTouchOfTwoApproachingShapesIsAnalytic) {
  // Circles of radius 1, 10 apart, closing at 16 per step: gap 8 closes at t = 0.5.
  const json r = ask(R"({"id": "toi", "op": "toi", "a": {"type": "circle", "radius": 1},
      "va": [8, 0], "b": {"type": "circle", "radius": 1}, "xb": {"p": [10, 0]}, "vb": [-8, 0]})");
  ASSERT_TRUE(r["hit"].get<bool>()) << r.dump();
  EXPECT_NEAR(r["t"].get<double>(), 0.5, 1e-3);
  EXPECT_NEAR(r["normal"][0].get<double>(), 1.0, 1e-4);
  EXPECT_NEAR(r["point"][0].get<double>(), 5.0, 1e-2);
  // A box fired at a thin wall far faster than its own size per step is still caught.
  const json wall = ask(R"({"op": "toi", "a": {"type": "box", "half": [0.1, 0.1]},
      "va": [1000, 0], "b": {"type": "segment", "a": [0, -1], "b": [0, 1]}, "xb": {"p": [500, 0]},
      "vb": [0, 0]})");
  ASSERT_TRUE(wall["hit"].get<bool>());
  EXPECT_NEAR(wall["t"].get<double>(), (500.0 - 0.1) / 1000.0, 1e-4);
  const json miss = ask(R"({"op": "toi", "a": {"type": "circle", "radius": 1}, "va": [0, 5],
      "b": {"type": "circle", "radius": 1}, "xb": {"p": [10, 0]}, "vb": [0, 0]})");
  EXPECT_FALSE(miss["hit"].get<bool>());
  const json already = ask(R"({"op": "toi", "a": {"type": "circle", "radius": 1}, "va": [1, 0],
      "b": {"type": "circle", "radius": 1}, "xb": {"p": [1, 0]}, "vb": [0, 0]})");
  ASSERT_TRUE(already["hit"].get<bool>());
  EXPECT_EQ(already["t"].get<double>(), 0.0);
  EXPECT_NE(error_of(R"({"op": "toi", "a": {"type": "circle", "radius": 1},
      "b": {"type": "circle", "radius": 1}, "vb": [0, 0]})").find("va: missing"),
            std::string::npos);
}

}  // namespace
}  // namespace collide::cli
