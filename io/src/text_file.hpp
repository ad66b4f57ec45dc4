#pragma once
// Private to collide_io: reading a whole input file, splitting its text into lines and words,
// reading a word as a number, and quoting its bytes in messages.

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

/// Longest piece of a line an error message quotes; longer ones are cut with "...".
inline constexpr std::size_t kMaxQuotedBytes = 40;

/// True for the blanks between words of a line-based format (OBJ, points): space and tab.
[[nodiscard]] inline bool is_blank(char c) noexcept { return c == ' ' || c == '\t'; }

/// The line of `text` that starts at `pos`, without its end ("\n", "\r\n" or "\r"); `pos`
/// moves past the end. Call while pos < text.size().
[[nodiscard]] std::string_view next_line(std::string_view text, std::size_t& pos) noexcept;

/// Splits off the next blank-separated word of `rest` (empty when none is left).
[[nodiscard]] std::string_view next_word(std::string_view& rest) noexcept;

/// `word` quoted for a message: printable ASCII as it is, other bytes as \xNN (so the message is
/// valid UTF-8 and holds no NUL), at most kMaxQuotedBytes of it.
[[nodiscard]] std::string quoted(std::string_view word);

/// What `parse_float_word` found.
enum class FloatWord : unsigned char {
  ok,            ///< a finite float (what underflows float is a valid 0)
  not_a_number,  ///< not a decimal number as a whole ("abc", "1.5x", "")
  not_finite,    ///< "nan", "inf", "infinity" in any case
  out_of_range,  ///< beyond float range ("1e39", "-1e999")
};

/// `word` read as a float: a decimal number as std::from_chars reads it (a leading '+' allowed
/// too), parsed as double and then checked against float range. `value` is set only when ok.
[[nodiscard]] FloatWord parse_float_word(std::string_view word, float& value) noexcept;

/// Appends byte `b` as "\xNN" (upper-case hex): how messages quoting raw input show a byte that
/// cannot stand as it is.
void append_hex_byte(std::string& out, unsigned char b);

/// `text` with every byte that is not part of well-formed UTF-8 written as "\xNN", so a message
/// quoting raw input is valid UTF-8 (Unicode 15, table 3-7: no overlong forms, no surrogates,
/// nothing above U+10FFFF).
[[nodiscard]] std::string valid_utf8(std::string_view text);

}  // namespace collide::io
