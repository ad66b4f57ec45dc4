// Reading a whole input file, bounded (kMaxInputFileBytes), without letting a stream exception
// out: on Linux a folder opens as a file and throws on the first read.

#include "text_file.hpp"

#include <algorithm>
#include <fstream>
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
