#pragma once
// What must hold for any bytes given to `collide query` as a line (fuzz_query_line, and the
// regression test that replays the inputs the fuzzer found): shared so both check the same.

#include "query.hpp"

#include <collide/core/error.hpp>

#include <nlohmann/json.hpp>

#include <exception>
#include <sstream>
#include <string>
#include <string_view>

namespace collide::fuzz {

/// True when `j` is or holds null: nlohmann writes a NaN or infinite number as null, and no
/// answer field may be either (the spec's answers are numbers, booleans, strings and arrays).
inline bool holds_null(const nlohmann::json& j) {
  if (j.is_null()) return true;
  if (j.is_structured()) {
    for (const nlohmann::json& e : j) {
      if (holds_null(e)) return true;
    }
  }
  return false;
}

/// "" when `reply`, the answer to a non-blank question line, is as the query spec says: one line
/// of valid UTF-8 JSON (nlohmann's strict parser is the judge), an object with "id" and either a
/// non-empty "error" string or answer fields, none of them null (a NaN or infinity); else what is
/// wrong with it.
inline std::string check_answer(const std::string& reply) {
  if (reply.empty()) return "a non-blank line not answered";
  if (reply.find('\n') != std::string::npos) return "answer spans lines: " + reply;
  nlohmann::json a;
  try {
    a = nlohmann::json::parse(reply);
  } catch (const std::exception& e) {
    return std::string("answer is not valid JSON (") + e.what() + "): " + reply;
  }
  if (!a.is_object() || !a.contains("id")) return "answer without id: " + reply;
  if (a.contains("error")) {
    if (!a["error"].is_string() || a["error"].get<std::string>().empty() || a.size() != 2) {
      return "malformed error answer: " + reply;
    }
  } else if (a.size() < 2) {
    return "answer with neither error nor result: " + reply;
  } else {
    for (const auto& [key, value] : a.items()) {
      if (key != "id" && holds_null(value)) return "answer holds null (a number that is not finite): " + reply;
    }
  }
  return {};
}

/// True when `text` holds only blanks (spaces, tabs, carriage returns, newlines).
inline bool blank(std::string_view text) { return text.find_first_not_of(" \t\r\n") == std::string_view::npos; }

/// "" when `input` is handled as the query spec says, else what went wrong:
///  - answer_query_stream, given `input` as a whole stream, throws nothing and answers each
///    non-blank line once, each answer as check_answer says. The stream answers a line with
///    answer_query_line (query.hpp), so for an input of one line this is answer_query_line's
///    contract too: "" for a blank line, else one line of valid JSON (check_answer);
///  - answer_query_line, given an input of several lines as one line, throws nothing and answers
///    as check_answer says; given "", answers "" (asked apart only then: the stream gives it
///    every other input, a line without '\n', as it is, and each question costs a parse);
///  - parse_cast_question (`collide cast --question`) throws nothing but InvalidInput.
/// Crashes and undefined behaviour are the sanitizers' to catch.
inline std::string check_query_line(std::string_view input) {
  std::size_t lines = 0;
  for (std::size_t start = 0; start <= input.size();) {
    const std::size_t end = std::min(input.find('\n', start), input.size());
    if (!blank(input.substr(start, end - start))) ++lines;
    start = end + 1;
  }
  try {
    std::istringstream in{std::string(input)};
    std::ostringstream out;
    const std::size_t answered = cli::answer_query_stream(in, out);
    if (answered != lines) {
      return "stream: " + std::to_string(answered) + " answers for " + std::to_string(lines) + " lines";
    }
    const std::string answers = out.str();
    std::size_t count = 0;
    for (std::size_t start = 0; start < answers.size(); ++count) {
      const std::size_t end = answers.find('\n', start);
      if (end == std::string::npos) return "stream: the last answer has no newline";
      if (std::string problem = check_answer(answers.substr(start, end - start)); !problem.empty()) {
        return "stream: " + problem;
      }
      start = end + 1;
    }
    if (count != answered) {
      return "stream: " + std::to_string(count) + " answer lines for " + std::to_string(answered) + " answers";
    }
  } catch (const std::exception& e) {
    return std::string("answer_query_stream threw: ") + e.what();
  }

  if (input.empty() || input.find('\n') != std::string_view::npos) {
    std::string reply;
    try {
      reply = cli::answer_query_line(input);
    } catch (const std::exception& e) {
      return std::string("answer_query_line threw: ") + e.what();
    }
    if (blank(input) != reply.empty()) return "blank line answered, or a line not answered: '" + reply + "'";
    if (!blank(input)) {
      if (std::string problem = check_answer(reply); !problem.empty()) return problem;
    }
  }

  try {
    (void)cli::parse_cast_question(input);
  } catch (const InvalidInput&) {
  } catch (const std::exception& e) {
    return std::string("parse_cast_question threw other than InvalidInput: ") + e.what();
  }
  return {};
}

}  // namespace collide::fuzz
