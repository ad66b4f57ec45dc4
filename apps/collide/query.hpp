#pragma once
// `collide query`: one JSON question in, one JSON answer out (../shared/spec/query-jsonl.md).

#include <collide/core/transform.hpp>
#include <collide/shape/shape2d.hpp>

#include <iosfwd>
#include <string>
#include <string_view>

namespace collide::cli {

/// The shapes and motions of a `toi` question (spec/query-jsonl.md): A placed by `xa` moving
/// by `va` over the step, B placed by `xb` moving by `vb`. World space.
struct CastQuestion {
  Shape2D a;
  Transform xa;
  Vec2 va{0.0f, 0.0f};
  Shape2D b;
  Transform xb;
  Vec2 vb{0.0f, 0.0f};
};

/// Parses one JSON object with the fields of a `toi` question (a, xa, va, b, xb, vb; "op", if
/// present, must be "toi"). Throws InvalidInput whose message names the field, as the query
/// protocol's errors do.
[[nodiscard]] CastQuestion parse_cast_question(std::string_view text);

/// The answer to one question line, as one line of JSON (no trailing newline). Never throws:
/// a line that cannot be answered gives {"id": ..., "error": "<why, naming the field>"}.
/// Returns an empty string for a blank line (which is skipped).
[[nodiscard]] std::string answer_query_line(std::string_view line);

/// Answers every line of `in` on `out`, in order. Returns the number of lines answered.
std::size_t answer_query_stream(std::istream& in, std::ostream& out);

/// Text listing the ops and their fields, for `collide query --help`.
[[nodiscard]] std::string query_ops_help();

}  // namespace collide::cli
