// What the .tmx and .tmj readers share: the limits one load spends, and external tilesets and
// templates read once per load.

#include "text_file.hpp"
#include "tiled_document.hpp"

#include <collide/core/error.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <unordered_map>

namespace collide::tiled {

void sort_tiles(TiledTileset& ts) {
  std::stable_sort(ts.tiles.begin(), ts.tiles.end(),
                   [](const TiledTile& a, const TiledTile& b) { return a.id < b.id; });
}

void sort_tilesets(TiledMap& map) {
  std::stable_sort(map.tilesets.begin(), map.tilesets.end(),
                   [](const TiledTileset& a, const TiledTileset& b) { return a.first_gid < b.first_gid; });
}

const TiledTileset* tileset_with_gid(const TiledMap& map, std::uint32_t id) {
  const auto& sets = map.tilesets;
  const auto it = std::upper_bound(sets.begin(), sets.end(), id,
                                   [](std::uint32_t key, const TiledTileset& t) { return key < t.first_gid; });
  if (it == sets.begin()) return nullptr;
  const std::uint32_t first = std::prev(it)->first_gid;
  return &*std::lower_bound(sets.begin(), it, first,
                            [](const TiledTileset& t, std::uint32_t key) { return t.first_gid < key; });
}

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

void check_tile_block(int x0, int y0, int width, int height, const std::filesystem::path& file,
                      std::string_view element) {
  if (static_cast<long long>(x0) + width > INT_MAX || static_cast<long long>(y0) + height > INT_MAX) {
    fail(file, element, "x + width or y + height is beyond " + std::to_string(INT_MAX));
  }
}

void add_tile_block(TileLayer& layer, int x0, int y0, int width, const std::vector<std::uint32_t>& gids) {
  for (std::size_t i = 0; i < gids.size(); ++i) {
    if (gids[i] != 0) {
      layer.cells.push_back({x0 + static_cast<int>(i % static_cast<std::size_t>(width)),
                             y0 + static_cast<int>(i / static_cast<std::size_t>(width)), gids[i]});
    }
  }
}

void check_tile_colliders(Document& doc) {
  std::unordered_map<std::uint32_t, std::size_t> shapes_of;  // by gid without flips
  std::size_t total = 0;
  for (const TileLayer& layer : doc.tile_layers) {
    for (const Cell& cell : layer.cells) {
      const std::uint32_t id = cell.gid & kTiledGidMask;
      auto it = shapes_of.find(id);
      if (it == shapes_of.end()) {
        std::size_t n = 0;
        if (const TiledTileset* set = tileset_with_gid(doc.map, id)) {
          if (const TiledTile* tile = set->find(static_cast<int>(id - set->first_gid))) n = tile->collision.size();
        }
        it = shapes_of.emplace(id, n).first;
      }
      total += it->second;
      if (total > kMaxTiledColliders) {
        fail(doc.map.path, "<layer name=" + layer.name + ">",
             "the tile layers' cells make more than " + std::to_string(kMaxTiledColliders) +
                 " colliders (the limit, kMaxTiledColliders)");
      }
    }
  }
}

Vec2 object_alignment_anchor(std::string_view value, const std::filesystem::path& file, std::string_view element) {
  // Tiled's ObjectAlignment names (Tiled 1.4); "unspecified" means bottom-left on orthogonal
  // maps, the only orientation collide reads.
  struct Named {
    std::string_view name;
    Vec2 anchor;
  };
  static constexpr Named kAlignments[] = {
      {"", {0.0f, 1.0f}},          {"unspecified", {0.0f, 1.0f}}, {"bottomleft", {0.0f, 1.0f}},
      {"topleft", {0.0f, 0.0f}},   {"top", {0.5f, 0.0f}},         {"topright", {1.0f, 0.0f}},
      {"left", {0.0f, 0.5f}},      {"center", {0.5f, 0.5f}},      {"right", {1.0f, 0.5f}},
      {"bottom", {0.5f, 1.0f}},    {"bottomright", {1.0f, 1.0f}},
  };
  for (const Named& a : kAlignments) {
    if (a.name == value) return a.anchor;
  }
  fail(file, element,
       "objectalignment '" + std::string(value) +
           "': not one of unspecified, topleft, top, topright, left, center, right, bottomleft, bottom, bottomright");
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
