// What the .tmx and .tmj readers share: the limits one load spends, and external tilesets and
// templates read once per load.

#include "text_file.hpp"
#include "tiled_document.hpp"

#include <collide/core/error.hpp>

#include <climits>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace collide::tiled {

void charge_bytes(Document& doc, std::size_t bytes, const std::filesystem::path& file) {
  doc.bytes += bytes;
  if (doc.bytes > kMaxTiledLoadBytes) {
    fail(file, "file", "the map and the files it uses come to more than " +
                           std::to_string(kMaxTiledLoadBytes) + " bytes (the limit, kMaxTiledLoadBytes)");
  }
}

void charge_tiles(Document& doc, std::uint64_t width, std::uint64_t height,
                  const std::filesystem::path& file, std::string_view element) {
  // width and height are at most INT_MAX each: the product fits in 64 bits.
  doc.declared_tiles += width * height;
  if (width * height > kMaxTiledMapTiles || doc.declared_tiles > kMaxTiledMapTiles) {
    fail(file, element, std::to_string(width) + " x " + std::to_string(height) +
                            " tiles make the map's tile layers declare " + std::to_string(doc.declared_tiles) +
                            " tiles, more than " + std::to_string(kMaxTiledMapTiles) +
                            " (the limit, kMaxTiledMapTiles)");
  }
}

TiledTileset external_tileset(Document& doc, const std::filesystem::path& file) {
  const std::string key = file.lexically_normal().generic_string();
  auto it = doc.tilesets.find(key);
  if (it == doc.tilesets.end()) {
    std::size_t bytes = 0;
    TiledTileset ts = read_tileset_file(file, bytes);
    it = doc.tilesets.emplace(key, std::make_pair(std::move(ts), bytes)).first;
  }
  charge_bytes(doc, it->second.second, file);
  return it->second.first;
}

const Template& external_template(Document& doc, const std::filesystem::path& file) {
  const std::string key = file.lexically_normal().generic_string();
  auto it = doc.templates.find(key);
  if (it == doc.templates.end()) {
    std::size_t bytes = 0;
    Template t = read_template(file, bytes);
    it = doc.templates.emplace(key, std::make_pair(std::move(t), bytes)).first;
  }
  charge_bytes(doc, it->second.second, file);
  return it->second.first;
}

std::string read_input(const std::filesystem::path& file) {
  std::string why;
  std::optional<std::string> text = io::read_text_file(file, why);
  if (!text) fail(file, "file", why);
  return std::move(*text);
}

void check_group_depth(int depth, const std::filesystem::path& file, std::string_view element) {
  if (depth > kMaxTiledGroupDepth) {
    fail(file, element, "group layers nested " + std::to_string(depth) + " deep, deeper than " +
                            std::to_string(kMaxTiledGroupDepth) + " (the limit, kMaxTiledGroupDepth)");
  }
}

long long whole_or_fail(double value, long long lo, long long hi, const std::filesystem::path& file,
                        std::string_view element, std::string_view field) {
  if (!std::isfinite(value) || value != std::floor(value)) {
    fail(file, element, std::string(field) + ": not an integer");
  }
  if (value < static_cast<double>(lo) || value > static_cast<double>(hi)) {
    std::ostringstream shown;
    shown << std::setprecision(17) << value;
    fail(file, element, std::string(field) + ": " + shown.str() + " is outside [" +
                            std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return static_cast<long long>(value);
}

}  // namespace collide::tiled
