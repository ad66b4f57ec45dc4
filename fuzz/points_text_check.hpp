#pragma once
// What must hold for any bytes given to the points reader (fuzz_points_text, and the regression
// test that replays the inputs the fuzzer found): shared so both check the same.

#include "fuzz_check.hpp"

#include <collide/core/error.hpp>
#include <collide/io/points_text.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

namespace collide::fuzz {

/// The lines of `text` that hold a point by collide/io/points_text.hpp's rule (not blank, not a
/// comment), counted here on their own.
inline std::size_t data_lines(std::string_view text) {
  std::size_t count = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = pos;
    while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
    std::size_t first = pos;
    while (first < end && (text[first] == ' ' || text[first] == '\t')) ++first;
    if (first < end && text[first] != '#') ++count;
    pos = end + (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n' ? 2 : 1);
  }
  return count;
}

/// "" when io::parse_points<D> handles `input` as collide/io/points_text.hpp says, else what
/// went wrong: it throws nothing but InvalidInput naming the file and a line ("points.txt:N: ")
/// in valid UTF-8; a list it accepts has one finite point per data line, and reads back the same
/// when written with 9 significant digits.
template <int D>
std::string check_points_text_dimension(std::string_view input) {
  const std::string name = "points.txt";
  std::vector<VecN<D>> points;
  try {
    points = io::parse_points<D>(input, name);
  } catch (const InvalidInput& e) {
    const std::string message = e.what();
    if (std::string problem = check_message(message, name + ":"); !problem.empty()) return problem;
    const std::size_t colon = message.find(':', name.size() + 1);
    if (colon == std::string::npos || colon == name.size() + 1 ||
        message.find_first_not_of("0123456789", name.size() + 1) != colon) {
      return "message does not name a line: " + message;
    }
    return {};
  } catch (const std::exception& e) {
    return std::string("parse_points threw other than InvalidInput: ") + e.what();
  }
  if (points.size() != data_lines(input)) {
    return std::to_string(points.size()) + " points for " + std::to_string(data_lines(input)) + " data lines";
  }
  std::string written;
  for (const VecN<D>& p : points) {
    for (int k = 0; k < D; ++k) {
      if (!std::isfinite(p[k])) return "an accepted point is not finite";
      char buf[32];
      std::snprintf(buf, sizeof buf, k + 1 < D ? "%.9g " : "%.9g\n", static_cast<double>(p[k]));
      written += buf;
    }
  }
  try {
    if (io::parse_points<D>(written, name) != points) return "the points written with %.9g read back differently";
  } catch (const std::exception& e) {
    return std::string("the accepted points, written with %.9g, are refused: ") + e.what();
  }
  return {};
}

/// Both dimensions' contract on `input`, and: 2D and 3D both accept it only when it holds no
/// point (a line cannot hold both two and three numbers).
inline std::string check_points_text(std::string_view input) {
  if (std::string problem = check_points_text_dimension<2>(input); !problem.empty()) return "2D: " + problem;
  if (std::string problem = check_points_text_dimension<3>(input); !problem.empty()) return "3D: " + problem;
  bool both = true;
  try {
    (void)io::parse_points<2>(input, "points.txt");
    (void)io::parse_points<3>(input, "points.txt");
  } catch (const InvalidInput&) {
    both = false;
  }
  if (both && data_lines(input) > 0) return "a file of points read as 2D and as 3D";
  return {};
}

}  // namespace collide::fuzz
