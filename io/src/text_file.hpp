#pragma once
// Private to collide_io: reading a whole input file, and quoting its bytes in messages.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace collide::io {

/// Largest input file any reader takes (Tiled maps, tilesets and templates, scene JSON, OBJ):
/// 64 MiB. A larger file, or one without end (/dev/zero, a FIFO), is refused after reading at
/// most kMaxInputFileBytes + 1 bytes: "file: larger than 67108864 bytes (the limit,
/// kMaxInputFileBytes)".
inline constexpr std::size_t kMaxInputFileBytes = std::size_t{64} << 20;

/// The bytes of the file at `path`, or nullopt with `why` set when it cannot be read: "cannot be
/// read" (missing, a folder, no permission, an I/O error) or "larger than N bytes (the limit,
/// kMaxInputFileBytes)". Works on files that are not regular (devices, FIFOs). Never throws for
/// those.
[[nodiscard]] std::optional<std::string> read_text_file(const std::filesystem::path& path,
                                                        std::string& why);

/// Appends byte `b` as "\xNN" (upper-case hex): how messages quoting raw input show a byte that
/// cannot stand as it is.
void append_hex_byte(std::string& out, unsigned char b);

/// `text` with every byte that is not part of well-formed UTF-8 written as "\xNN", so a message
/// quoting raw input is valid UTF-8 (Unicode 15, table 3-7: no overlong forms, no surrogates,
/// nothing above U+10FFFF).
[[nodiscard]] std::string valid_utf8(std::string_view text);

}  // namespace collide::io
