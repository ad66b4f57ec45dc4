// The `collide query` protocol: answers checked against analytic geometry, every rejection in the
// spec's error list answered with an error naming the field, and the stream going on after it.

#include "query.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

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
  EXPECT_NE(error_of(R"({"op": "overlap", "a": {"type": "circle", "radius": 1e999}})").find("not valid JSON"),
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
