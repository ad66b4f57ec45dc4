#pragma once
// Private to collide_io: what the JSON readers (Tiled .tmj, scene JSON) share.

#include <cstddef>
#include <string>
#include <string_view>

namespace collide::io {

/// Appends the member name `key` to a path being written: as it is, but with control
/// characters written \u00XX (as JSON escapes them), so a path is printable text with no NUL
/// that would cut a C string short.
void append_path_key(std::string& path, std::string_view key);

/// Offset in `text` of the bracket that opens nesting level `max_depth` + 1 (the root object
/// or array is level 1), or npos: a scan of [ and { outside strings, so deep nesting is refused
/// before a recursive parser or destructor could overflow the stack. Unbalanced or malformed
/// text is left for the parser to reject.
[[nodiscard]] std::size_t json_too_deep_at(std::string_view text, std::size_t max_depth);

/// Steps of a path `json_path_at_syntax_error` writes out; deeper ones are cut to "...".
inline constexpr std::size_t kMaxShownPathSteps = 16;

/// Where in `text` (malformed JSON, or JSON cut short) the parser was when it failed: the path
/// of the element being read, "layers[0].objects[3] (id=12).polygon[2]" (an object's numeric "id"
/// member, once read, is shown after its index), "root" at the top level; the first
/// kMaxShownPathSteps steps, then "...". Parses `text` again; load time only.
[[nodiscard]] std::string json_path_at_syntax_error(std::string_view text);

}  // namespace collide::io
