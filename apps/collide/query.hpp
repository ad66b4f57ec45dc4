#pragma once
// `collide query`: one JSON question in, one JSON answer out (../shared/spec/query-jsonl.md).

#include <collide/core/transform.hpp>
#include <collide/shape/shape2d.hpp>

#include <cstddef>
#include <iosfwd>
#include <string>
#include <string_view>

namespace collide::cli {

/// Longest question line `collide query` reads, in bytes (without the newline): 16 MiB. A longer
/// line is skipped unread and answered {"id": null, "error": "line N: longer than ..."}, so no
/// input makes the tool hold more than this per line.
inline constexpr std::size_t kMaxQueryLineBytes = std::size_t{16} << 20;

/// The shapes and motions of a 2D `toi` question (spec/query-jsonl.md), as `collide cast` draws
/// them: A placed by `xa` moving by `va` over the step, B placed by `xb` moving by `vb`. World
/// space.
struct CastQuestion {
  Shape2D a;
  Transform xa;
  Vec2 va{0.0f, 0.0f};
  Shape2D b;
  Transform xb;
  Vec2 vb{0.0f, 0.0f};
};

/// Parses one JSON object with the fields of a `toi` question (a, xa, va, b, xb, vb; "op", if
/// present, must be "toi"), in 2D: a field telling 3D is rejected ("a.center: 3D coordinates, in
/// a 2D question (collide cast draws 2D questions only)"). Throws InvalidInput whose message
/// names the field, as the query protocol's errors do (a JsonFieldError for a bad field,
/// collide/io/shape_json.hpp).
[[nodiscard]] CastQuestion parse_cast_question(std::string_view text);

/// The answer to one question line, as one line of valid UTF-8 JSON (no trailing newline). A
/// line that cannot be answered (bad JSON, bytes that are not UTF-8, nesting deeper than
/// kMaxJsonDepth, a bad field, even running out of memory) gives {"id": ..., "error": "<why,
/// naming the field>"}. Returns an empty string for a blank line (which is skipped). Throws
/// nothing but std::bad_alloc, and that only if not even a fixed error answer can be made.
[[nodiscard]] std::string answer_query_line(std::string_view line);

/// Answers every line of `in` on `out`, in order, each answer followed by '\n': a line (its
/// bytes as they are, without the '\n') gets answer_query_line's answer, none when that is
/// empty (a blank line); lines longer than kMaxQueryLineBytes are answered with an error and
/// not read. Returns the number of lines answered. Throws std::runtime_error ("read error after
/// line N") when `in` fails other than by ending.
std::size_t answer_query_stream(std::istream& in, std::ostream& out);

/// `collide query [FILE]`: answers FILE (standard input when empty or "-") on `out`. Returns the
/// exit status: 0 when the input was read to its end (unanswerable lines get error answers), 2
/// with one line on `err` when it cannot be read (missing, a folder, an I/O error), the answers
/// cannot be written, or anything else fails (an exception of any kind, out of memory).
[[nodiscard]] int run_query(const std::string& file, std::istream& standard_input, std::ostream& out,
                            std::ostream& err);

/// Text listing the ops and their fields, for `collide query --help`.
[[nodiscard]] std::string query_ops_help();

}  // namespace collide::cli
