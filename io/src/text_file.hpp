#pragma once
// Private to collide_io: reading a whole input file.

#include <filesystem>
#include <optional>
#include <string>

namespace collide::io {

/// The bytes of the file at `path`, or nullopt when it cannot be opened or read (missing, a
/// folder, no permission, an I/O error). Never throws for those.
[[nodiscard]] std::optional<std::string> read_text_file(const std::filesystem::path& path);

}  // namespace collide::io
