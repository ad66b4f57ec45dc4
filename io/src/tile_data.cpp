// Tile layer data: csv, base64 (OpenSSL's decoder), zlib/gzip (zlib's inflate), zstd (libzstd).
// The decoded size is the declared width x height (within kMaxTiledMapTiles, checked by the
// caller), and no decoder writes past it: a small stream that inflates to gigabytes stops there.

#include "tiled_document.hpp"

#include <openssl/evp.h>
#include <zlib.h>
#include <zstd.h>

#include <cctype>
#include <charconv>
#include <climits>
#include <string>

namespace collide::tiled {
namespace {

std::vector<unsigned char> base64_decode(std::string_view text, const std::filesystem::path& file,
                                         std::string_view element) {
  std::string clean;
  clean.reserve(text.size());
  for (char c : text) {
    if (!std::isspace(static_cast<unsigned char>(c))) clean.push_back(c);
  }
  if (clean.size() % 4 != 0 || clean.size() > static_cast<size_t>(INT_MAX)) {
    fail(file, element, "base64 tile data: length " + std::to_string(clean.size()) +
                            " is not a multiple of 4");
  }
  std::vector<unsigned char> out(clean.size() / 4 * 3);
  const int n = EVP_DecodeBlock(out.data(), reinterpret_cast<const unsigned char*>(clean.data()),
                                static_cast<int>(clean.size()));
  if (n < 0) fail(file, element, "base64 tile data: invalid base64");
  // EVP_DecodeBlock counts the bytes that '=' padding stands for; drop them.
  size_t size = static_cast<size_t>(n);
  for (size_t i = clean.size(); i > 0 && clean[i - 1] == '=' && size > 0; --i) --size;
  out.resize(size);
  return out;
}

std::vector<unsigned char> inflate_all(const std::vector<unsigned char>& in, size_t expected,
                                       const std::filesystem::path& file,
                                       std::string_view element) {
  std::vector<unsigned char> out(expected);
  z_stream zs{};
  // 15 + 32: accept both zlib and gzip headers.
  if (inflateInit2(&zs, 15 + 32) != Z_OK) fail(file, element, "tile data: zlib init failed");
  zs.next_in = const_cast<unsigned char*>(in.data());
  zs.avail_in = static_cast<uInt>(in.size());
  zs.next_out = out.data();
  zs.avail_out = static_cast<uInt>(out.size());
  const int rc = inflate(&zs, Z_FINISH);
  const size_t produced = out.size() - zs.avail_out;
  const bool full = zs.avail_out == 0;
  inflateEnd(&zs);
  if (rc != Z_STREAM_END) {
    fail(file, element,
         std::string("compressed tile data: ") +
             (rc != Z_BUF_ERROR ? "corrupt stream"
              : full            ? "more data than width x height tiles"
                                : "the stream ends early"));
  }
  out.resize(produced);
  return out;
}

/// zstd (Tiled 1.3+): decompresses at most `expected` bytes; more fails.
std::vector<unsigned char> zstd_all(const std::vector<unsigned char>& in, size_t expected,
                                    const std::filesystem::path& file, std::string_view element) {
  std::vector<unsigned char> out(expected);
  ZSTD_DStream* zs = ZSTD_createDStream();
  if (zs == nullptr) fail(file, element, "tile data: zstd init failed");
  ZSTD_inBuffer input{in.data(), in.size(), 0};
  ZSTD_outBuffer output{out.data(), out.size(), 0};
  size_t rc = 1;
  // Until a frame ends (rc == 0), the input is used up, or the output is full.
  while (rc != 0 && !ZSTD_isError(rc)) {
    const size_t before_in = input.pos, before_out = output.pos;
    rc = ZSTD_decompressStream(zs, &output, &input);
    if (input.pos == before_in && output.pos == before_out) break;  // no progress
  }
  // Probe one byte past `expected`: a stream that still has data is too long.
  unsigned char extra = 0;
  ZSTD_outBuffer probe{&extra, 1, 0};
  const bool more = rc != 0 && !ZSTD_isError(rc) && output.pos == out.size() &&
                    (ZSTD_decompressStream(zs, &probe, &input), probe.pos > 0);
  ZSTD_freeDStream(zs);
  if (ZSTD_isError(rc)) {
    fail(file, element, std::string("compressed tile data: corrupt zstd stream (") + ZSTD_getErrorName(rc) + ")");
  }
  if (more) fail(file, element, "compressed tile data: more data than width x height tiles");
  if (rc != 0) fail(file, element, "compressed tile data: the zstd stream ends early");
  out.resize(output.pos);
  return out;
}

}  // namespace

std::vector<std::uint32_t> decode_tile_data(std::string_view text, std::string_view encoding,
                                            std::string_view compression, size_t count,
                                            const std::filesystem::path& file,
                                            std::string_view element) {
  std::vector<std::uint32_t> gids;
  gids.reserve(count);
  if (encoding == "csv") {
    if (!compression.empty()) fail(file, element, "csv tile data cannot be compressed");
    size_t pos = 0;
    while (pos < text.size()) {
      size_t end = text.find(',', pos);
      if (end == std::string_view::npos) end = text.size();
      std::string_view item = text.substr(pos, end - pos);
      while (!item.empty() && std::isspace(static_cast<unsigned char>(item.front()))) item.remove_prefix(1);
      while (!item.empty() && std::isspace(static_cast<unsigned char>(item.back()))) item.remove_suffix(1);
      pos = end + 1;
      if (item.empty() && end == text.size()) break;  // trailing comma or whitespace
      if (gids.size() == count) {
        fail(file, element, "csv tile data: more than the " + std::to_string(count) + " tiles of width x height");
      }
      std::uint32_t gid = 0;
      const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), gid);
      if (ec != std::errc() || ptr != item.data() + item.size()) {
        fail(file, element, "csv tile data: '" + std::string(item) + "' is not a tile gid");
      }
      gids.push_back(gid);
    }
  } else if (encoding == "base64") {
    std::vector<unsigned char> bytes = base64_decode(text, file, element);
    if (compression == "zlib" || compression == "gzip") {
      bytes = inflate_all(bytes, count * 4, file, element);
    } else if (compression == "zstd") {
      bytes = zstd_all(bytes, count * 4, file, element);
    } else if (!compression.empty()) {
      fail(file, element, "tile data compression '" + std::string(compression) +
                              "' is not supported (use zlib, gzip, zstd or none)");
    }
    if (bytes.size() != count * 4) {
      fail(file, element, "tile data: " + std::to_string(bytes.size() / 4) + " tiles, expected " +
                              std::to_string(count));
    }
    for (size_t i = 0; i < count; ++i) {  // little-endian 32-bit gids
      gids.push_back(static_cast<std::uint32_t>(bytes[4 * i]) |
                     static_cast<std::uint32_t>(bytes[4 * i + 1]) << 8 |
                     static_cast<std::uint32_t>(bytes[4 * i + 2]) << 16 |
                     static_cast<std::uint32_t>(bytes[4 * i + 3]) << 24);
    }
  } else {
    fail(file, element, "tile data encoding '" + std::string(encoding) + "' is not supported");
  }
  if (gids.size() != count) {
    fail(file, element, "tile data: " + std::to_string(gids.size()) + " tiles, expected " +
                            std::to_string(count));
  }
  return gids;
}

}  // namespace collide::tiled
