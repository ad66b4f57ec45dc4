#pragma once
// `collide query`: one JSON question in, one JSON answer out (../shared/spec/query-jsonl.md).

#include <iosfwd>
#include <string>
#include <string_view>

namespace collide::cli {

/// The answer to one question line, as one line of JSON (no trailing newline). Never throws:
/// a line that cannot be answered gives {"id": ..., "error": "<why, naming the field>"}.
/// Returns an empty string for a blank line (which is skipped).
[[nodiscard]] std::string answer_query_line(std::string_view line);

/// Answers every line of `in` on `out`, in order. Returns the number of lines answered.
std::size_t answer_query_stream(std::istream& in, std::ostream& out);

/// Text listing the ops and their fields, for `collide query --help`.
[[nodiscard]] std::string query_ops_help();

}  // namespace collide::cli
