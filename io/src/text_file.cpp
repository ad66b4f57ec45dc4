// Reading a whole input file, bounded (kMaxInputFileBytes), without letting a stream exception
// out: on Linux a folder opens as a file and throws on the first read.

#include "text_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <system_error>

namespace collide::io {

std::optional<std::string> read_text_file(const std::filesystem::path& path, std::string& why) {
  why = "cannot be read";
  // Whether the size a file reports or the bytes it gives go past the limit, the same words.
  static const std::string too_large =
      "larger than " + std::to_string(kMaxInputFileBytes) + " bytes (the limit, kMaxInputFileBytes)";
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return std::nullopt;
  try {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    // Read in blocks up to one byte past the limit: the size a file reports is not trusted (a
    // device or a FIFO reports none, a file may grow while it is read).
    std::string text;
    // The first block: the whole of a regular file (and one byte more, to see its end), else 64 KiB.
    std::size_t block = std::size_t{1} << 16;
    if (std::filesystem::is_regular_file(path, ec)) {  // refuse a big file without reading it
      const auto size = std::filesystem::file_size(path, ec);
      if (!ec && size > kMaxInputFileBytes) {
        why = too_large;
        return std::nullopt;
      }
      if (!ec) block = static_cast<std::size_t>(size) + 1;
    }
    while (text.size() <= kMaxInputFileBytes) {
      const std::size_t old = text.size();
      const std::size_t want = std::min(block, kMaxInputFileBytes + 1 - old);
      block = std::max(block, std::size_t{1} << 20);  // later blocks: 1 MiB
      text.resize(old + want);
      in.read(text.data() + old, static_cast<std::streamsize>(want));
      const auto got = static_cast<std::size_t>(in.gcount());
      text.resize(old + got);
      if (in.bad()) return std::nullopt;
      if (got < want) break;  // end of file
    }
    if (text.size() > kMaxInputFileBytes) {
      why = too_large;
      return std::nullopt;
    }
    why.clear();
    return text;
  } catch (const std::exception&) {  // std::ios_base::failure from the stream buffer
    return std::nullopt;
  }
}

std::string_view next_line(std::string_view text, std::size_t& pos) noexcept {
  std::size_t end = pos;
  while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
  const std::string_view line = text.substr(pos, end - pos);
  pos = end + (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n' ? 2 : 1);
  return line;
}

std::string_view next_word(std::string_view& rest) noexcept {
  std::size_t i = 0;
  while (i < rest.size() && is_blank(rest[i])) ++i;
  std::size_t end = i;
  while (end < rest.size() && !is_blank(rest[end])) ++end;
  const std::string_view word = rest.substr(i, end - i);
  rest.remove_prefix(end);
  return word;
}

std::string quoted(std::string_view word) {
  std::string out = "'";
  for (std::size_t i = 0; i < word.size() && i < kMaxQuotedBytes; ++i) {
    const auto c = static_cast<unsigned char>(word[i]);
    if (c >= 0x20 && c < 0x7F) {
      out += static_cast<char>(c);
    } else {
      append_hex_byte(out, c);
    }
  }
  if (word.size() > kMaxQuotedBytes) out += "...";
  return out + "'";
}

FloatWord parse_float_word(std::string_view word, float& value) noexcept {
  if (word.size() > 1 && word.front() == '+') word.remove_prefix(1);  // from_chars takes no '+'
  // Parsed as double: what underflows float is a valid 0, what overflows it is not.
  double parsed = 0.0;
  const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), parsed);
  const bool whole = ptr == word.data() + word.size();
  if (ec == std::errc() && whole && !std::isfinite(parsed)) return FloatWord::not_finite;
  // Out of float range means rounding to infinity: from 2^128 - 2^103, the midpoint between
  // FLT_MAX and 2^128, up (a tie rounds to even, which is 2^128). Below it a word rounds to a
  // finite float, FLT_MAX at most: "3.4028235e38" and FLT_MAX written with 9 digits,
  // "3.40282347e+38", are both FLT_MAX (the fuzzer found the second refused while the first
  // was read, so a point written back with %.9g could not be read again).
  constexpr double kFloatOverflow = 0x1.ffffffp+127;
  if (ec == std::errc::result_out_of_range || std::fabs(parsed) >= kFloatOverflow) {
    return FloatWord::out_of_range;
  }
  if (ec != std::errc() || !whole) return FloatWord::not_a_number;
  value = static_cast<float>(parsed);
  return FloatWord::ok;
}

void append_hex_byte(std::string& out, unsigned char b) {
  constexpr char kHex[] = "0123456789ABCDEF";
  out += "\\x";
  out += kHex[b >> 4];
  out += kHex[b & 15];
}

/// `text` with every byte that is not part of well-formed UTF-8 written as "\xNN", so a message
/// quoting raw input is valid UTF-8 (Unicode 15, table 3-7: no overlong forms, no surrogates,
/// nothing above U+10FFFF).
std::string valid_utf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char b = byte(i);
    std::size_t n = 0;          // continuation bytes
    unsigned char lo = 0x80, hi = 0xBF;  // range of the first continuation byte
    if (b < 0x80) n = 0;
    else if (b >= 0xC2 && b <= 0xDF) n = 1;
    else if (b == 0xE0) { n = 2; lo = 0xA0; }
    else if (b >= 0xE1 && b <= 0xEC) n = 2;
    else if (b == 0xED) { n = 2; hi = 0x9F; }
    else if (b >= 0xEE && b <= 0xEF) n = 2;
    else if (b == 0xF0) { n = 3; lo = 0x90; }
    else if (b >= 0xF1 && b <= 0xF3) n = 3;
    else if (b == 0xF4) { n = 3; hi = 0x8F; }
    else n = 4;  // never a first byte
    bool ok = n < 4 && i + n < text.size();  // i + n: the sequence's last byte
    if (ok && n > 0) {
      ok = byte(i + 1) >= lo && byte(i + 1) <= hi;
      for (std::size_t k = 2; ok && k <= n; ++k) ok = byte(i + k) >= 0x80 && byte(i + k) <= 0xBF;
    }
    if (ok) {
      out.append(text.substr(i, n + 1));
      i += n + 1;
    } else {
      append_hex_byte(out, b);
      ++i;
    }
  }
  return out;
}

}  // namespace collide::io
