#pragma once
/// @file
/// One set of status words for every iterative query (GJK distance, shape casts, time of
/// impact, EPA): DESIGN.md, "one convention each".

#include <cstdint>

namespace collide {

/// How an iterative query ended.
enum class QueryStatus : std::uint8_t {
  /// The shapes are apart (a distance query), or stay apart over the whole motion (a cast).
  separated,
  /// The shapes touch or overlap: at the query's configuration, or at the start of a cast.
  overlapped,
  /// A cast: the shapes first touch at the reported fraction of the motion, in (0, 1].
  hit,
  /// The method stopped before it converged: its iteration cap was reached, or it could make
  /// no further progress within float rounding. The result is its best estimate, on the safe
  /// side where the query says so (a cast's fraction: no contact before it).
  max_iterations,
};

/// Lower-case name of a status ("separated", "overlapped", "hit", "max_iterations").
[[nodiscard]] constexpr const char* to_string(QueryStatus s) noexcept {
  switch (s) {
    case QueryStatus::separated: return "separated";
    case QueryStatus::overlapped: return "overlapped";
    case QueryStatus::hit: return "hit";
    case QueryStatus::max_iterations: return "max_iterations";
  }
  return "?";
}

}  // namespace collide
