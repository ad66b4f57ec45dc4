// The `collide query` protocol: answers checked against analytic geometry, every rejection in the
// spec's error list answered with an error naming the field, and the stream going on after it.

#include "query.hpp"

#include "cli_run.hpp"

#include <collide/broad/registry.hpp>
#include <collide/ccd/raycast.hpp>
#include <collide/io/shape_json.hpp>
#include <collide/narrow/closest_point.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/overlap.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>
#include <cstdio>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <streambuf>
#include <sys/wait.h>
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
  EXPECT_EQ(error_of("{not json").rfind("root: JSON syntax error at line 1, column 3: ", 0), 0u);
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
                .find("a.vertices: polygon"),
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
  EXPECT_NE(error_of(R"({"id": 1, "op": "overlap", "a": 1e400,)").find("JSON syntax error"),
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

// Issue 15: `collide query` never dies on a line, whatever it holds, and says when its input
// cannot be read. Each case below crashed, hung on to the input or exited 0 before the fix.
namespace collide::cli {
namespace {

using test::exit_code;
using test::run_shell;

const std::string kGoodQuestion = R"({"id": 2, "op": "overlap", "a": {"type": "circle", "radius": 1}, "b": {"type": "circle", "radius": 1}})";

// A byte that is not UTF-8 made nlohmann's syntax error quote it raw; writing the answer then
// threw outside any handler (std::terminate).
TEST(QueryRobustness, BytesThatAreNotUtf8GiveAValidUtf8ErrorAnswer) {
  for (const std::string bad : {"\xff", "\xc3", "\xe2\x82", "\xed\xa0\x80", "\xc0\xaf", "\xf4\x90\x80\x80"}) {
    const std::string line = "{\"id\": \"" + bad + "\", \"op\": \"overlap\"}";
    std::string reply;
    ASSERT_NO_THROW(reply = answer_query_line(line));
    json a;
    ASSERT_NO_THROW(a = json::parse(reply)) << reply;  // strict: throws on bytes that are not UTF-8
    EXPECT_TRUE(a["id"].is_null());
    EXPECT_EQ(a.value("error", "").rfind("id: JSON syntax error at line 1, column ", 0), 0u) << reply;
    EXPECT_NE(a.value("error", "").find("\\x"), std::string::npos) << reply;  // the byte, as text
  }
  // Through the tool: the line is answered and so is the next one.
  const test::CommandRun r = run_shell("printf '{\"id\": \"\\377\"}\\n%s\\n' '" + kGoodQuestion + "' | \"$COLLIDE\" query");
  EXPECT_EQ(exit_code(r), 0) << r.output;
  EXPECT_NE(r.output.find("JSON syntax error"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(R"({"id":2,"overlap":true})"), std::string::npos) << r.output;
}

// 100,000 nested arrays overflowed the stack (copying the id, printing it).
TEST(QueryRobustness, NestingDeeperThanTheLimitIsAnErrorNamingIt) {
  const auto nested = [](std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); };
  for (const std::size_t depth : {kMaxJsonDepth, kMaxJsonDepth + 1, std::size_t{100000}}) {
    // The root object is level 1, so an id of `depth` arrays reaches level depth + 1.
    const std::string line = R"({"id": )" + nested(depth - 1) + R"(, "op": "overlap", "a": {"type": "circle", "radius": 1},
        "b": {"type": "circle", "radius": 1}})";
    const json a = ask(line);
    if (depth <= kMaxJsonDepth) {
      EXPECT_TRUE(a.value("overlap", false)) << a.dump().substr(0, 200);
      continue;
    }
    const std::string error = a.value("error", "");
    EXPECT_EQ(error.rfind("id[0][0]", 0), 0u) << error;  // where: in the id
    EXPECT_NE(error.find("JSON nested deeper than 256 levels (the limit) at line 1, column "), std::string::npos) << error;
    EXPECT_LT(error.size(), 200u) << "the path is cut short, not 256 steps long";
  }
  // Brackets inside strings are not nesting.
  EXPECT_FALSE(ask(R"({"id": ")" + std::string(1000, '[') + R"(", "op": "overlap", "a": {"type": "circle", "radius": 1},
      "b": {"type": "circle", "radius": 1}})").contains("error"));
  const test::CommandRun r = run_shell("python3 -c \"print('{\\\"id\\\": ' + '[' * 100000 + ']' * 100000 + '}')\" | \"$COLLIDE\" query");
  EXPECT_EQ(exit_code(r), 0) << r.output.substr(0, 300);
  EXPECT_NE(r.output.find("nested deeper than 256 levels"), std::string::npos) << r.output.substr(0, 300);
}

// A folder opened as a file read nothing, and the tool said nothing and exited 0; a missing file
// exited 1 (every other command says 2 for input it cannot read).
TEST(QueryRobustness, InputThatCannotBeReadExitsWithStatus2) {
  const std::string folder = ::testing::TempDir() + "query_folder";
  std::filesystem::create_directories(folder);
  test::CommandRun r = run_shell("\"$COLLIDE\" query '" + folder + "'");
  EXPECT_EQ(exit_code(r), 2) << r.output;
  EXPECT_NE(r.output.find("collide query: " + folder + ": cannot be read (a directory)"), std::string::npos) << r.output;
  r = run_shell("\"$COLLIDE\" query /nonexistent/questions.jsonl");
  EXPECT_EQ(exit_code(r), 2) << r.output;
  EXPECT_NE(r.output.find("collide query: /nonexistent/questions.jsonl: cannot be read"), std::string::npos) << r.output;
  // Answers that cannot be written are an error too (a full disk).
  r = run_shell("{ \"$COLLIDE\" query '" + std::string(COLLIDE_EXAMPLES_DIR) + "/queries.jsonl' > /dev/full; }");
  EXPECT_EQ(exit_code(r), 2) << r.output;
  EXPECT_NE(r.output.find("could not be written"), std::string::npos) << r.output;
}

// A line longer than kMaxQueryLineBytes is answered with an error and not kept in memory.
TEST(QueryRobustness, LinesLongerThanTheLimitAreSkippedWithAnError) {
  const std::string pad_head = R"({"id": 1, "pad": ")";
  const std::string pad_tail = R"(", "op": "overlap", "a": {"type": "circle", "radius": 1}, "b": {"type": "circle", "radius": 1}})";
  std::string at_limit = pad_head + std::string(kMaxQueryLineBytes - pad_head.size() - pad_tail.size(), 'x') + pad_tail;
  ASSERT_EQ(at_limit.size(), kMaxQueryLineBytes);
  std::string over = at_limit;
  over.insert(pad_head.size(), "x");
  std::istringstream in(at_limit + "\n" + over + "\n" + kGoodQuestion + "\n" + over);  // the last has no newline
  std::ostringstream out;
  EXPECT_EQ(answer_query_stream(in, out), 4u);
  std::istringstream lines(out.str());
  std::string a1, a2, a3, a4;
  std::getline(lines, a1);
  std::getline(lines, a2);
  std::getline(lines, a3);
  std::getline(lines, a4);
  EXPECT_EQ(a1, R"({"id":1,"overlap":true})");
  EXPECT_EQ(a2, R"({"error":"line 2: longer than 16777216 bytes (the limit, 16 MiB); not read","id":null})");
  EXPECT_EQ(a3, R"({"id":2,"overlap":true})");
  EXPECT_EQ(a4, R"({"error":"line 4: longer than 16777216 bytes (the limit, 16 MiB); not read","id":null})");
}

// A 100 MB line under a 100 MB address-space limit: std::getline's std::bad_alloc was swallowed
// by the stream, which then ended: exit 0 with no answer at all, not even for the good line after.
TEST(QueryRobustness, AHugeLineUnderAMemoryLimitIsAnsweredAndTheNextLineToo) {
#ifdef COLLIDE_TEST_UNDER_ASAN
  GTEST_SKIP() << "ulimit -v and AddressSanitizer's shadow memory do not mix";
#else
  const test::CommandRun r = run_shell(
      "(printf '{\"id\": 1, \"pad\": \"'; head -c 100000000 /dev/zero | tr '\\0' a; printf '\"}\\n%s\\n' '" + kGoodQuestion +
      "') | (ulimit -v 100000; \"$COLLIDE\" query)");
  EXPECT_EQ(exit_code(r), 0) << r.output;
  EXPECT_EQ(r.output, R"({"error":"line 1: longer than 16777216 bytes (the limit, 16 MiB); not read","id":null})"
                      "\n"
                      R"({"id":2,"overlap":true})"
                      "\n");
#endif
}

/// A stream buffer that throws `E` on its first read, as a failing device or allocator would.
template <class E>
struct ThrowingBuffer : std::streambuf {
  int_type underflow() override { throw E(); }
};
struct DeviceError : std::runtime_error {
  DeviceError() : std::runtime_error("device error") {}
};

// Whatever goes wrong around the lines is a message and exit status 2, never an abort.
TEST(QueryRobustness, AnyExceptionOnTheCommandPathIsStatus2WithAMessage) {
  {
    ThrowingBuffer<std::bad_alloc> buf;
    std::istream in(&buf);
    in.exceptions(std::ios::badbit);  // let the stream pass the exception on
    std::ostringstream out, err;
    EXPECT_EQ(run_query("-", in, out, err), 2);
    EXPECT_EQ(err.str(), "collide query: standard input: out of memory\n");
  }
  {
    ThrowingBuffer<DeviceError> buf;  // a read error the stream keeps to itself (badbit)
    std::istream in(&buf);
    std::ostringstream out, err;
    EXPECT_EQ(run_query("", in, out, err), 2);
    EXPECT_EQ(err.str(), "collide query: standard input: read error after line 0\n");
  }
  std::istringstream in(kGoodQuestion + "\n");
  std::ostringstream out, err;
  EXPECT_EQ(run_query("-", in, out, err), 0);
  EXPECT_EQ(out.str(), "{\"id\":2,\"overlap\":true}\n");
  EXPECT_EQ(err.str(), "");
}

// Shapes and transforms take exactly their fields (and "comment"), as in scene files; the
// question object itself may carry more (the shipped examples carry "expect_error").
TEST(QueryRobustness, UnknownFieldsOfShapesAndTransformsAreNamed) {
  EXPECT_EQ(error_of(R"({"op": "overlap", "a": {"type": "circle", "radius": 1, "centre": [0, 0]},
      "b": {"type": "circle", "radius": 1}})"),
            "a.centre: unknown field (expected one of: type, center, radius, comment)");
  EXPECT_EQ(error_of(R"({"op": "overlap", "a": {"type": "circle", "radius": 1},
      "b": {"type": "circle", "radius": 1}, "xb": {"p": [1, 0], "rot": 1}})"),
            "xb.rot: unknown field (expected one of: p, angle, comment)");
  EXPECT_EQ(error_of(R"({"op": "overlap", "a": {"type": "polygon", "concave": true, "vertices": [[0, 0], [1, 0], [0, 1]]},
      "b": {"type": "circle", "radius": 1}})"),
            "a.concave: a concave polygon is several convex pieces; one convex shape is expected here");
  EXPECT_EQ(error_of(R"({"op": "closest_point", "shape": {"type": "polyline", "points": [[0, 0], [1, 0]]}, "point": [0, 0]})"),
            "shape.type: a polyline is several convex pieces; one convex shape is expected here");
  const json ok = ask(R"({"id": 3, "note": "ignored", "op": "overlap", "a": {"type": "circle", "radius": 1, "comment": "x"},
      "b": {"type": "circle", "radius": 1}, "xb": {"p": [3, 0], "comment": {"any": [1]}}})");
  EXPECT_EQ(ok.dump(), R"({"id":3,"overlap":false})");
}

}  // namespace
}  // namespace collide::cli

// 3D: every op of the spec with 3-number coordinates, checked against analytic answers; lines
// that mix dimensions or hold bad 3D values answered with an error naming the field.
namespace collide::cli {
namespace {

double num(const json& j) { return j.get<double>(); }

/// |a - b| for JSON arrays of numbers.
double gap(const json& a, const std::vector<double>& b) {
  double s = 0.0;
  EXPECT_EQ(a.size(), b.size()) << a.dump();
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) s += (num(a[k]) - b[k]) * (num(a[k]) - b[k]);
  return std::sqrt(s);
}

TEST(Query3D, OverlapAndDistanceOfTwoSpheresAreAnalytic) {
  // Centres 3 apart along (2, 2, 1) / 3: the gap is 1, the closest points on the line of centres.
  const json d = ask(R"({"id": "d3", "op": "distance", "a": {"type": "sphere", "center": [0, 0, 0], "radius": 1},
      "b": {"type": "sphere", "radius": 1}, "xb": {"p": [2, 2, 1], "q": [0.6, 0.8, 0, 0]}})");
  EXPECT_EQ(d["id"], "d3");
  EXPECT_NEAR(num(d["distance"]), 1.0, 1e-5) << d.dump();
  EXPECT_LT(gap(d["pa"], {2.0 / 3, 2.0 / 3, 1.0 / 3}), 1e-5) << d.dump();
  EXPECT_LT(gap(d["pb"], {4.0 / 3, 4.0 / 3, 2.0 / 3}), 1e-5) << d.dump();
  // A sphere without center is 3D when the rest of the question is (here the transform says so).
  for (const double x : {1.9, 2.0, 2.1}) {
    const json o = ask(R"({"op": "overlap", "a": {"type": "sphere", "radius": 1}, "b": {"type": "sphere", "radius": 1},
        "xb": {"p": [0, 0, )" + std::to_string(x) + "]}}");
    EXPECT_EQ(o["overlap"].get<bool>(), x <= 2.0) << x << " " << o.dump();
  }
  // Box and capsule: the capsule's core ends 0.5 above the box's top face, radius 0.25.
  const json bc = ask(R"({"op": "distance", "a": {"type": "box", "half": [1, 1, 1]},
      "b": {"type": "capsule", "a": [0, 0, 0], "b": [0, 2, 0], "radius": 0.25}, "xb": {"p": [0.2, 1.5, -0.3]}})");
  EXPECT_NEAR(num(bc["distance"]), 0.25, 1e-5) << bc.dump();
  EXPECT_NEAR(num(bc["pa"][1]), 1.0, 1e-5);
  EXPECT_NEAR(num(bc["pb"][1]), 1.25, 1e-5);
}

TEST(Query3D, ContactOfStackedBoxesHasFourPointsWithFeatures) {
  // A unit cube turned a quarter about y (the same cube) resting 0.1 deep on a wide box.
  const double c = std::sqrt(0.5);
  const json m = ask(R"({"op": "contact", "a": {"type": "box", "half": [2, 1, 2]},
      "b": {"type": "box", "half": [1, 1, 1]}, "xb": {"p": [0, 1.9, 0], "q": [)" + std::to_string(c) + ", 0, " +
                     std::to_string(c) + ", 0]}}");
  ASSERT_TRUE(m["touching"].get<bool>()) << m.dump();
  EXPECT_LT(gap(m["normal"], {0, 1, 0}), 1e-5) << m.dump();
  EXPECT_NEAR(num(m["depth"]), 0.1, 1e-4);
  ASSERT_EQ(m["points"].size(), 4u) << m.dump();
  ASSERT_EQ(m["features"].size(), 4u);
  ASSERT_EQ(m["depths"].size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(num(m["points"][i][1]), 0.95, 1e-4);  // midway between the surfaces y = 1 and 0.9
    EXPECT_NEAR(std::abs(num(m["points"][i][0])), 1.0, 1e-4);
    EXPECT_NEAR(std::abs(num(m["points"][i][2])), 1.0, 1e-4);
    EXPECT_NEAR(num(m["depths"][i]), 0.1, 1e-4);
    ASSERT_EQ(m["features"][i].size(), 2u);
    for (const json& f : m["features"][i]) {
      const std::string s = f.get<std::string>();
      EXPECT_TRUE(s.starts_with("vertex ") || s.starts_with("edge ") || s.starts_with("face ")) << s;
    }
  }
  // A's top face is face 3 (+y: 2 * 1 + 1): the reference face of every point.
  EXPECT_EQ(m["features"][0][0], "face 3") << m.dump();
  const json apart = ask(R"({"op": "contact", "a": {"type": "sphere", "radius": 1}, "b": {"type": "sphere", "radius": 1},
      "xb": {"p": [0, 0, 3]}})");
  EXPECT_FALSE(apart["touching"].get<bool>());
  EXPECT_FALSE(apart.contains("normal"));
  // Sphere on a hull's face: normal from A (the hull) to B.
  const json s = ask(R"({"op": "contact", "a": {"type": "hull", "points": [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
      [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]]}, "b": {"type": "sphere", "radius": 0.5}, "xb": {"p": [0, 0, 1.4]}})");
  ASSERT_TRUE(s["touching"].get<bool>()) << s.dump();
  EXPECT_LT(gap(s["normal"], {0, 0, 1}), 1e-5) << s.dump();
  EXPECT_NEAR(num(s["depth"]), 0.1, 1e-5);
  EXPECT_EQ(s["points"].size(), 1u);
}

TEST(Query3D, RaycastAgainstBoxesHullsAndATriangle) {
  const json r = ask(R"({"op": "raycast", "shape": {"type": "box", "half": [1, 1, 1]}, "x": {"p": [10, 0, 0]},
      "origin": [0, 0, 0], "translation": [20, 0, 0]})");
  ASSERT_TRUE(r["hit"].get<bool>()) << r.dump();
  EXPECT_NEAR(num(r["fraction"]), 9.0 / 20.0, 1e-6);
  EXPECT_LT(gap(r["normal"], {-1, 0, 0}), 1e-6);
  EXPECT_LT(gap(r["point"], {9, 0, 0}), 1e-5);
  // Turned 45 degrees about z, the ray meets the box's edge at x = 10 - sqrt(2).
  const json e = ask(R"({"op": "raycast", "shape": {"type": "box", "half": [1, 1, 1]},
      "x": {"p": [10, 0, 0], "q": [0.9238795325, 0, 0, 0.3826834324]}, "origin": [0, 0, 0], "translation": [20, 0, 0]})");
  ASSERT_TRUE(e["hit"].get<bool>()) << e.dump();
  EXPECT_NEAR(num(e["fraction"]), (10.0 - std::sqrt(2.0)) / 20.0, 1e-5);
  // A ray starting inside reports no hit.
  EXPECT_FALSE(ask(R"({"op": "raycast", "shape": {"type": "sphere", "radius": 1}, "origin": [0, 0, 0.5],
      "translation": [0, 0, 5]})")["hit"].get<bool>());
  // A tetrahedron hull: the ray down the z axis enters the face x + y + z = 1 at z = 1.
  const json h = ask(R"({"op": "raycast", "shape": {"type": "hull", "points": [[0, 0, 0], [3, 0, 0], [0, 3, 0], [0, 0, 3]]},
      "origin": [0.5, 0.5, 10], "translation": [0, 0, -20]})");
  ASSERT_TRUE(h["hit"].get<bool>()) << h.dump();
  EXPECT_NEAR(num(h["fraction"]), (10.0 - 2.0) / 20.0, 1e-5);
  const double n = 1.0 / std::sqrt(3.0);
  EXPECT_LT(gap(h["normal"], {n, n, n}), 1e-5) << h.dump();
  // A triangle is two-sided: hit from below at z = 5, the normal facing the ray.
  const json t = ask(R"({"op": "raycast", "shape": {"type": "triangle", "vertices": [[-1, -1, 0], [1, -1, 0], [0, 1, 0]]},
      "x": {"p": [0, 0, 5]}, "origin": [0, 0, 0], "translation": [0, 0, 10]})");
  ASSERT_TRUE(t["hit"].get<bool>()) << t.dump();
  EXPECT_NEAR(num(t["fraction"]), 0.5, 1e-6);
  EXPECT_NEAR(std::abs(num(t["normal"][2])), 1.0, 1e-6);
}

TEST(Query3D, ClosestPointNamesTheVoronoiFeature) {
  const json out = ask(R"({"op": "closest_point", "shape": {"type": "box", "half": [1, 2, 3]}, "point": [5, 0, 0]})");
  EXPECT_FALSE(out["inside"].get<bool>());
  EXPECT_NEAR(num(out["distance"]), 4.0, 1e-6);
  EXPECT_LT(gap(out["closest"], {1, 0, 0}), 1e-6);
  EXPECT_EQ(out["feature"], "face 1");  // +x
  const json in = ask(R"({"op": "closest_point", "shape": {"type": "box", "half": [1, 2, 3]}, "point": [0.5, 0, 0]})");
  EXPECT_TRUE(in["inside"].get<bool>());
  EXPECT_NEAR(num(in["distance"]), -0.5, 1e-6);
  EXPECT_EQ(in["feature"], "face 1");
  // Beyond the corner (+x, +y, +z) of the box placed at (10, 0, 0): vertex 7, sqrt(3) away.
  const json v = ask(R"({"op": "closest_point", "shape": {"type": "box", "half": [1, 1, 1]}, "x": {"p": [10, 0, 0]},
      "point": [12, 2, 2]})");
  EXPECT_EQ(v["feature"], "vertex 7");
  EXPECT_NEAR(num(v["distance"]), std::sqrt(3.0), 1e-5);
  EXPECT_LT(gap(v["closest"], {11, 1, 1}), 1e-5);
  const json s = ask(R"({"op": "closest_point", "shape": {"type": "sphere", "center": [1, 0, 0], "radius": 2},
      "point": [1, 0, 5]})");
  EXPECT_NEAR(num(s["distance"]), 3.0, 1e-6);
  EXPECT_LT(gap(s["closest"], {1, 0, 2}), 1e-6);
}

TEST(Query3D, TimeOfImpactOfApproachingShapesIsAnalytic) {
  // Spheres of radius 1, 10 apart along z, closing at 16 per step: the gap of 8 closes at 0.5.
  const json r = ask(R"({"op": "toi", "a": {"type": "sphere", "radius": 1}, "va": [0, 0, 8],
      "b": {"type": "sphere", "radius": 1}, "xb": {"p": [0, 0, 10]}, "vb": [0, 0, -8]})");
  ASSERT_TRUE(r["hit"].get<bool>()) << r.dump();
  EXPECT_NEAR(num(r["t"]), 0.5, 1e-3);
  EXPECT_LT(gap(r["normal"], {0, 0, 1}), 1e-4);
  EXPECT_LT(gap(r["point"], {0, 0, 5}), 1e-2);
  // A small box fired at a thin wall (a hull slab) far faster than its size per step.
  const json wall = ask(R"({"op": "toi", "a": {"type": "box", "half": [0.1, 0.1, 0.1]}, "va": [1000, 0, 0],
      "b": {"type": "box", "half": [0.01, 2, 2]}, "xb": {"p": [500, 0, 0]}, "vb": [0, 0, 0]})");
  ASSERT_TRUE(wall["hit"].get<bool>()) << wall.dump();
  EXPECT_NEAR(num(wall["t"]), (500.0 - 0.11) / 1000.0, 1e-4);
  EXPECT_LT(gap(wall["normal"], {1, 0, 0}), 1e-4);
  EXPECT_FALSE(ask(R"({"op": "toi", "a": {"type": "sphere", "radius": 1}, "va": [0, 5, 0],
      "b": {"type": "sphere", "radius": 1}, "xb": {"p": [10, 0, 0]}, "vb": [0, 0, 0]})")["hit"].get<bool>());
  const json already = ask(R"({"op": "toi", "a": {"type": "capsule", "a": [0, 0, 0], "b": [0, 1, 0], "radius": 0.5},
      "va": [1, 0, 0], "b": {"type": "sphere", "radius": 1}, "xb": {"p": [1, 0, 0]}, "vb": [0, 0, 0]})");
  ASSERT_TRUE(already["hit"].get<bool>());
  EXPECT_EQ(num(already["t"]), 0.0);
}

TEST(Query3D, LinesMixingDimensionsAreRejectedNamingTheField) {
  EXPECT_EQ(error_of(R"({"op": "overlap", "a": {"type": "circle", "center": [0, 0], "radius": 1},
      "xa": {"p": [0, 0, 0]}, "b": {"type": "circle", "radius": 1}})"),
            "xa.p: 3D coordinates, in a 2D question (told by a.center)");
  EXPECT_EQ(error_of(R"({"op": "overlap", "a": {"type": "box", "half": [1, 1]}, "xa": {"q": [1, 0, 0, 0]},
      "b": {"type": "circle", "radius": 1}})"),
            "xa.q: a quaternion is a 3D rotation, in a 2D question (told by a.half)");
  EXPECT_EQ(error_of(R"({"op": "distance", "a": {"type": "sphere", "center": [0, 0, 0], "radius": 1},
      "b": {"type": "sphere", "radius": 1}, "xb": {"p": [3, 0, 0], "angle": 1}})"),
            "xb.angle: an angle is a 2D rotation, in a 3D question (told by a.center)");
  EXPECT_EQ(error_of(R"({"op": "contact", "a": {"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]},
      "b": {"type": "polygon", "vertices": [[0, 0], [1, 0], [0, 1]]}})"),
            "b.type: \"polygon\" is a 2D shape, in a 3D question (told by a.type)");
  EXPECT_EQ(error_of(R"({"op": "contact", "a": {"type": "box", "half": [1, 1, 1]},
      "b": {"type": "circle", "radius": 1}})"),
            "b.type: a \"circle\" without center is 2D, in a 3D question (told by a.half); give it a 3-number "
            "center or call it \"sphere\"");
  EXPECT_EQ(error_of(R"({"op": "raycast", "shape": {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]},
      "origin": [0, 0], "translation": [0, 0, 1]})"),
            "origin: 2D coordinates, in a 3D question (told by shape.type)");
  EXPECT_EQ(error_of(R"({"op": "closest_point", "shape": {"type": "sphere", "radius": 1}, "point": [0, 0, 3],
      "x": {"p": [1, 2]}})"),
            "point: 3D coordinates, in a 2D question (told by x.p)");
  EXPECT_EQ(error_of(R"({"op": "toi", "a": {"type": "sphere", "radius": 1}, "b": {"type": "sphere", "radius": 1},
      "va": [1, 0, 0], "vb": [0, 0]})"),
            "vb: 2D coordinates, in a 3D question (told by va)");
  EXPECT_EQ(error_of(R"({"op": "overlap", "a": {"type": "capsule", "a": [0, 0, 0], "b": [0, 1], "radius": 1},
      "b": {"type": "sphere", "radius": 1}})"),
            "a.b: expected 3 numbers, got 2 (2D coordinates where 3D is expected)");
  // `collide cast` draws 2D questions: a 3D one is refused by name.
  try {
    (void)parse_cast_question(R"({"a": {"type": "sphere", "center": [0, 0, 0], "radius": 1}, "b": {"type": "circle", "radius": 1},
        "va": [1, 0], "vb": [0, 0]})");
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "a.center: 3D coordinates, in a 2D question (collide cast draws 2D questions only)");
  }
}

TEST(Query3D, BadQuaternionsAndNonFiniteNumbersAreNamed) {
  const std::string spheres = R"("op": "overlap", "a": {"type": "sphere", "radius": 1}, "b": {"type": "sphere", "radius": 1}, )";
  EXPECT_EQ(error_of("{" + spheres + R"("xb": {"p": [1, 0, 0], "q": [1, 0, 0, 0.1]}})"),
            "xb.q: not a unit quaternion (length 1.00499; must be within 0.001 of 1)");
  EXPECT_EQ(error_of("{" + spheres + R"("xb": {"p": [1, 0, 0], "q": [0, 0, 0, 0]}})"),
            "xb.q: not a unit quaternion (length 0; must be within 0.001 of 1)");
  EXPECT_EQ(error_of("{" + spheres + R"("xb": {"q": [1, 0, 0]}})"), "xb.q: expected 4 numbers [w, x, y, z], got 3");
  EXPECT_EQ(error_of("{" + spheres + R"("xb": {"q": [1, 0, 0, 1e39]}})"), "xb.q[3]: not a finite float (1e+39)");
  EXPECT_EQ(error_of("{" + spheres + R"("xa": {"p": [0, 1e400, 0]}})"),
            "xa.p[1]: not a finite float (1e400 is beyond double range)");
  // Within 1e-3 of unit length: normalised, and answered as the unit rotation.
  const json near = ask("{" + spheres + R"("xb": {"p": [0, 0, 2.5], "q": [1.0009, 0, 0, 0]}})");
  EXPECT_FALSE(near.contains("error")) << near.dump();
  EXPECT_FALSE(near["overlap"].get<bool>());
  // JSON has no NaN: the word is a syntax error, the line still answered.
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "sphere", "radius": NaN}, "b": {"type": "sphere", "radius": 1}})")
                .find("JSON syntax error"),
            std::string::npos);
  EXPECT_EQ(error_of(R"({"op": "overlap", "a": {"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, "x"]]},
      "b": {"type": "sphere", "radius": 1}})"),
            "a.points[3][2]: expected a number, got string");
}

TEST(Query3D, BadShapesAreNamed) {
  const auto err = [](const std::string& shape) {
    return error_of(R"({"op": "overlap", "a": )" + shape + R"(, "b": {"type": "sphere", "center": [0, 0, 0], "radius": 1}})");
  };
  EXPECT_EQ(err(R"({"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]})"),
            "a.points: convex hull points: needs at least 4, got 3");
  EXPECT_EQ(err(R"({"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 3, 0]]})").rfind("a.points: convex hull points: ", 0),
            0u);
  EXPECT_NE(err(R"({"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 3, 0]]})").find("coplanar"),
            std::string::npos);
  EXPECT_EQ(err(R"({"type": "hull", "points": {}})"), "a.points: expected an array of [x, y, z] points, got object");
  EXPECT_EQ(err(R"({"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], "radius": -1})"),
            "a.radius: negative (-1)");
  EXPECT_EQ(err(R"({"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]})"),
            "a.vertices: a triangle has exactly 3 vertices, got 4");
  EXPECT_EQ(err(R"({"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0]]})"),
            "a.vertices: triangle: degenerate (repeated or collinear vertices, no area)");
  EXPECT_EQ(err(R"({"type": "box", "half": [1, 0, 1]})"), "a.half: half extents must be > 0");
  EXPECT_EQ(err(R"({"type": "capsule", "a": [0, 0, 0], "b": [0, 0, 0], "radius": 1})"),
            "a: capsule: a and b coincide (use a sphere)");
  EXPECT_EQ(err(R"({"type": "segment", "a": [0, 0, 0], "b": [0, 0, 0]})"), "a: segment: a and b coincide");
  EXPECT_EQ(err(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "half": [1, 1, 1]})"),
            "a.half: unknown field (expected one of: type, center, radius, comment)");
  EXPECT_EQ(err(R"({"type": "sphere", "center": [0, 0, 0], "radius": -2})"), "a.radius: negative (-2)");
}

// A hull's cost grows with its points: the count is capped (kMaxJsonHullPoints), and a hull
// needing more vertices than the library holds is refused rather than silently approximated.
TEST(Query3D, HugeHullsAreBoundedAndNamed) {
  const auto hull_line = [](std::size_t n, bool on_sphere) {
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0.0, 1.0);
    std::string line = R"({"id": "big", "op": "distance", "a": {"type": "hull", "points": [)";
    for (std::size_t i = 0; i < n; ++i) {
      double p[3] = {g(rng), g(rng), g(rng)};
      const double len = on_sphere ? std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) : 4.0;
      line += (i ? ",[" : "[") + std::to_string(p[0] / len) + "," + std::to_string(p[1] / len) + "," +
              std::to_string(p[2] / len) + "]";
    }
    return line + R"(]}, "b": {"type": "sphere", "center": [5, 0, 0], "radius": 1}})";
  };
  EXPECT_EQ(error_of(hull_line(kMaxJsonHullPoints + 1, false)),
            "a.points: 100001 points; at most 100000 (the limit, kMaxJsonHullPoints)");
  EXPECT_EQ(error_of(hull_line(kMaxJsonHullPoints, true)),
            "a.points: the convex hull of these 100000 points has more than 256 vertices (the library's limit, "
            "kMaxHullVertices)");
  // Many points, few hull vertices (a Gaussian cloud): answered; the hull spans about +-1.
  const json ok = ask(hull_line(5000, false));
  ASSERT_FALSE(ok.contains("error")) << ok.dump().substr(0, 300);
  EXPECT_GT(num(ok["distance"]), 2.5);
  EXPECT_LT(num(ok["distance"]), 4.0);
  // Every stored point of the answer is finite.
  EXPECT_EQ(ok["pa"].size(), 3u);
}

TEST(Query3D, EachBadLineIsAnsweredAndTheStreamGoesOn) {
  const std::string good = R"({"id": 1, "op": "overlap", "a": {"type": "sphere", "radius": 1}, "b": {"type": "box", "half": [1, 1, 1]}, "xb": {"p": [0, 0, 1.5]}})";
  const std::string deep = R"({"id": 2, "op": "overlap", "a": {"type": "hull", "points": )" + std::string(300, '[') +
                           std::string(300, ']') + R"(}, "b": {"type": "sphere", "radius": 1}})";
  const std::string quat = R"({"id": 3, "op": "distance", "a": {"type": "sphere", "radius": 1}, "b": {"type": "sphere", "radius": 1}, "xb": {"q": [2, 0, 0, 0]}})";
  const std::string mixed = R"({"id": 4, "op": "contact", "a": {"type": "box", "half": [1, 1, 1]}, "b": {"type": "box", "half": [1, 1]}})";
  const std::string hull = R"({"id": 5, "op": "raycast", "shape": {"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]}, "origin": [0.1, 0.1, -1], "translation": [0, 0, 2]})";
  std::istringstream in(good + "\n" + deep + "\n" + quat + "\n\n" + mixed + "\n" + hull + "\n");
  std::ostringstream out;
  EXPECT_EQ(answer_query_stream(in, out), 5u);
  std::istringstream lines(out.str());
  std::vector<json> a;
  for (std::string l; std::getline(lines, l);) a.push_back(json::parse(l));
  ASSERT_EQ(a.size(), 5u);
  EXPECT_EQ(a[0].dump(), R"({"id":1,"overlap":true})");
  EXPECT_EQ(a[1]["id"], nullptr);  // too deep to be read at all
  EXPECT_NE(a[1].value("error", "").find("JSON nested deeper than 256 levels"), std::string::npos) << a[1].dump();
  EXPECT_EQ(a[2]["id"], 3);
  EXPECT_EQ(a[2].value("error", ""), "xb.q: not a unit quaternion (length 2; must be within 0.001 of 1)");
  EXPECT_EQ(a[3]["id"], 4);
  EXPECT_EQ(a[3].value("error", ""), "b.half: 2D coordinates, in a 3D question (told by a.half)");
  EXPECT_EQ(a[4]["id"], 5);
  ASSERT_TRUE(a[4]["hit"].get<bool>()) << a[4].dump();
  EXPECT_NEAR(num(a[4]["fraction"]), 0.5, 1e-6);
}

template <class A, class B>
concept HasOverlap = requires(const A& a, const B& b, const Transform3& x) { overlap(a, x, b, x); };
template <class A, class B>
concept HasDistance = requires(const A& a, const B& b, const Transform3& x) { distance(a, x, b, x); };
template <class A, class B>
concept HasContact = requires(const A& a, const B& b, const Transform3& x) { contact(a, x, b, x); };
template <class S>
concept HasClosestPoint = requires(const S& s, const Transform3& x, Vec3 p) { closest_point(s, x, p); };

// Coordinates near the float range overflow a query's arithmetic: the answer is an error, never a
// NaN written as null (as it was, in 2D too: `"depth": null`).
TEST(Query3D, ResultsThatOverflowFloatAreAnErrorNotNull) {
  const std::string overflow = "no finite answer: the result overflowed float arithmetic (coordinates or sizes too large)";
  EXPECT_EQ(error_of(R"({"op": "contact", "a": {"type": "box", "half": [3e38, 3e38, 3e38]},
      "b": {"type": "box", "half": [1, 1, 1]}, "xb": {"p": [0, 3e38, 0]}})"),
            overflow);
  EXPECT_EQ(error_of(R"({"op": "closest_point", "shape": {"type": "hull", "points": [[0, 0, 0], [3e38, 0, 0], [0, 3e38, 0],
      [0, 0, 3e38]]}, "point": [-3e38, -3e38, -3e38]})"),
            overflow);
  EXPECT_EQ(error_of(R"({"op": "contact", "a": {"type": "box", "half": [3e38, 3e38]}, "b": {"type": "box", "half": [1, 1]},
      "xb": {"p": [0, 3e38]}})"),
            overflow);
  for (const char* file : {"extreme_coordinates2d.jsonl", "extreme_coordinates3d.jsonl"}) {
    std::ifstream in(std::string(COLLIDE_FUZZ_DIR) + "/seeds/query_line/" + file);
    int lines = 0;
    for (std::string line; std::getline(in, line); ++lines) {
      const json a = ask(line);
      for (const auto& [key, value] : a.items()) {
        if (key != "id") EXPECT_FALSE(value.is_null() || value.dump().find("null") != std::string::npos) << a.dump();
      }
    }
    EXPECT_GE(lines, 2) << file;
  }
}

// Pairs the library has no routine for yet are answered "unsupported", naming both shapes; once
// the library declares the overload (in either order) the tool answers it, and this test then
// checks the answer instead.
TEST(Query3D, PairsTheLibraryLacksAreNamedUntilItHasThem) {
  const std::string sphere_over_triangle =
      R"("a": {"type": "sphere", "center": [0.2, 0.2, 0.5], "radius": 1},
         "b": {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]})";
  constexpr bool has_overlap = HasOverlap<Sphere, Triangle> || HasOverlap<Triangle, Sphere>;
  const json o = ask(R"({"op": "overlap", )" + sphere_over_triangle + "}");
  if constexpr (has_overlap) {
    EXPECT_TRUE(o.value("overlap", false)) << o.dump();
  } else {
    EXPECT_EQ(o.value("error", ""), "unsupported pair: the library has no overlap for a sphere (a) and a triangle (b) yet");
  }
  constexpr bool has_distance = HasDistance<Sphere, Triangle> || HasDistance<Triangle, Sphere>;
  const json d = ask(R"({"op": "distance", "a": {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]},
      "b": {"type": "sphere", "center": [0.2, 0.2, 3], "radius": 1}})");
  if constexpr (has_distance) {
    EXPECT_NEAR(d.value("distance", -1.0), 2.0, 1e-5) << d.dump();
    EXPECT_LT(gap(d["pa"], {0.2, 0.2, 0}), 1e-5) << d.dump();  // on the triangle (a)
  } else {
    EXPECT_EQ(d.value("error", ""), "unsupported pair: the library has no distance for a triangle (a) and a sphere (b) yet");
  }
  constexpr bool has_contact = HasContact<Sphere, Triangle> || HasContact<Triangle, Sphere>;
  const json c = ask(R"({"op": "contact", )" + sphere_over_triangle + "}");
  if constexpr (has_contact) {
    EXPECT_LT(gap(c["normal"], {0, 0, -1}), 1e-5) << c.dump();  // from the sphere (a) down to the triangle
    EXPECT_NEAR(c.value("depth", -1.0), 0.5, 1e-5) << c.dump();
  } else {
    EXPECT_EQ(c.value("error", ""), "unsupported pair: the library has no contact for a sphere (a) and a triangle (b) yet");
  }
  constexpr bool has_closest = HasClosestPoint<Triangle>;
  const json p = ask(R"({"op": "closest_point", "shape": {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]},
      "point": [0.2, 0.2, 3]})");
  if constexpr (has_closest) {
    EXPECT_NEAR(p.value("distance", -1.0), 3.0, 1e-5) << p.dump();
    EXPECT_EQ(p.value("feature", ""), "face 0");
  } else {
    EXPECT_EQ(p.value("error", ""), "unsupported shape: the library has no closest_point for a triangle (shape) yet");
  }
}

}  // namespace
}  // namespace collide::cli
