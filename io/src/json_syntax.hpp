#pragma once
// Private to collide_io: what the JSON readers (Tiled .tmj, scene JSON) share.

#include <string>

namespace collide::io {

/// Where in `text` (malformed JSON) the parser was when it failed: the path of the element being
/// read, "layers[0].objects[3] (id=12).polygon[2]" (an object's numeric "id" member, once read,
/// is shown after its index), "root" at the top level. Parses `text` again; load time only.
[[nodiscard]] std::string json_path_at_syntax_error(const std::string& text);

}  // namespace collide::io
