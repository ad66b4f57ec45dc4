#pragma once
// Private to collide_io: what the .tmx and .tmj readers hand to the collider builder, and the
// helpers both readers share.

#include <collide/io/tiled.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace collide::tiled {

/// A non-empty cell of a tile layer.
struct Cell {
  int x = 0;               ///< column (may be negative in infinite maps)
  int y = 0;               ///< row
  std::uint32_t gid = 0;   ///< with flip bits
};

/// A tile layer, flattened out of its groups.
struct TileLayer {
  std::string name;               ///< path, groups joined by '/'
  Vec2 offset{0.0f, 0.0f};        ///< summed offsets of the layer and its groups
  std::vector<Cell> cells;
};

/// A parsed map before colliders are built: `map` holds header, tilesets and objects.
struct Document {
  TiledMap map;
  std::vector<TileLayer> tile_layers;
};

/// Throws InvalidInput "<file>: <element>: <message>".
[[noreturn]] void fail(const std::filesystem::path& file, std::string_view element,
                       std::string_view message);

/// Decodes a layer's or chunk's tile data into exactly `count` gids (row-major).
/// `encoding` is "csv" or "base64"; `compression` is "", "zlib" or "gzip" ("zstd" and others
/// are rejected). Errors go through `fail(file, element, ...)`.
[[nodiscard]] std::vector<std::uint32_t> decode_tile_data(std::string_view text,
                                                          std::string_view encoding,
                                                          std::string_view compression,
                                                          size_t count,
                                                          const std::filesystem::path& file,
                                                          std::string_view element);

/// Reads a .tmx (XML) map.
[[nodiscard]] Document read_tmx(const std::filesystem::path& file);
/// Reads a .tmj/.json map.
[[nodiscard]] Document read_tmj(const std::filesystem::path& file);

/// An external tileset file (.tsx XML, or .tsj/.json), with `first_gid` set by the caller.
[[nodiscard]] TiledTileset read_tileset_file(const std::filesystem::path& file);
/// A .tsj/.json tileset file (read_tileset_file dispatches here).
[[nodiscard]] TiledTileset read_tileset_json(const std::filesystem::path& file);

/// A template file (.tx XML): its object, and the tileset its gid refers to (if any).
struct Template {
  TiledObject object;
  bool has_gid = false;
  std::filesystem::path tileset_source;  ///< resolved .tsx of the template's gid
  std::uint32_t tileset_first_gid = 1;   ///< first gid of that tileset in the template
  bool has_shape = false;                 ///< the template names its kind (ellipse, polygon...)
};
/// A template file: .tx (XML) or .tj (JSON).
[[nodiscard]] Template read_template(const std::filesystem::path& file);
/// A .tj template (read_template dispatches here).
[[nodiscard]] Template read_template_json(const std::filesystem::path& file);

/// The gid of a template object rewritten for `map`: the template's tileset is looked up among
/// the map's tilesets by file (and appended to them when the map does not use it yet).
[[nodiscard]] std::uint32_t map_template_gid(TiledMap& map, const Template& t);

/// Both readers check numbers the same way: finite, else fail naming the field.
float finite_or_fail(double value, const std::filesystem::path& file, std::string_view element,
                     std::string_view field);

}  // namespace collide::tiled
