#pragma once
// Private to collide_io: what the .tmx and .tmj readers hand to the collider builder, and the
// helpers both readers share.

#include <collide/io/tiled.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
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

/// A template file (.tx XML or .tj JSON): its object, and the tileset its gid refers to (if any).
struct Template {
  TiledObject object;
  bool has_gid = false;
  std::filesystem::path tileset_source;  ///< resolved .tsx of the template's gid
  std::uint32_t tileset_first_gid = 1;   ///< first gid of that tileset in the template
};

/// True when an object as read names a shape of its own (ellipse, point, text, polygon,
/// polyline); false for the tile or rectangle an object without one falls back to. For a
/// template's object (templates do not nest) this is whether the template names the kind.
[[nodiscard]] inline bool has_own_shape(const TiledObject& obj) {
  return obj.kind != TiledShapeKind::tile && obj.kind != TiledShapeKind::rectangle;
}

/// A parsed map before colliders are built: `map` holds header, tilesets and objects. Also what
/// one load has spent of its limits, and the external files it has read (each is read once).
struct Document {
  TiledMap map;
  std::vector<TileLayer> tile_layers;
  std::uint64_t declared_tiles = 0;  ///< width x height over the layers and chunks read so far
  std::size_t bytes = 0;             ///< the map plus every use of an external file
  std::map<std::string, std::pair<TiledTileset, std::size_t>> tilesets;  ///< by path: file, size
  std::map<std::string, std::pair<Template, std::size_t>> templates;     ///< by path: file, size
  std::map<std::string, std::uint32_t> template_tilesets;  ///< tileset path -> its first gid in the map
};

/// Sorts a tileset's tiles by id (stable: of equal ids the first in the file is found), as
/// TiledTileset::find needs.
void sort_tiles(TiledTileset& ts);
/// Sorts the map's tilesets by first gid (stable), as the collider builder's lookup needs.
void sort_tilesets(TiledMap& map);

/// The tileset of `map` whose gid range holds `id` (a gid without flip bits): the last whose
/// first gid is <= id, the first of several with that first gid; nullptr when `id` is below
/// every first gid. Binary search: the readers sort the tilesets by first gid (sort_tilesets).
[[nodiscard]] const TiledTileset* tileset_with_gid(const TiledMap& map, std::uint32_t id);

/// Adds `bytes` to what the load has read; fails naming `file` past kMaxTiledLoadBytes.
void charge_bytes(Document& doc, std::size_t bytes, const std::filesystem::path& file);

/// Adds a layer's or chunk's width x height to the map's declared tiles; fails naming the file
/// and element past kMaxTiledMapTiles (before anything is decoded or reserved).
void charge_tiles(Document& doc, std::uint64_t width, std::uint64_t height,
                  const std::filesystem::path& file, std::string_view element);

/// An external tileset, read once per load (cached by path) and charged on every use.
[[nodiscard]] TiledTileset external_tileset(Document& doc, const std::filesystem::path& file);
/// An external template, read once per load (cached by path) and charged on every use.
[[nodiscard]] const Template& external_template(Document& doc, const std::filesystem::path& file);

/// The text of an input file (kMaxInputFileBytes at most); fails "<file>: file: <why>" when it
/// cannot be read.
[[nodiscard]] std::string read_input(const std::filesystem::path& file);

/// Fails naming `file` and `element` unless the cells of a width x height block of tile data at
/// (x0, y0) have int coordinates: x0 + width and y0 + height must fit (so must the row below the
/// last, which places a tile).
void check_tile_block(int x0, int y0, int width, int height, const std::filesystem::path& file,
                      std::string_view element);
/// Appends to `layer` the non-empty cells of a block of tile data `width` wide at (x0, y0):
/// gids[i] is cell (x0 + i % width, y0 + i / width). check_tile_block first.
void add_tile_block(TileLayer& layer, int x0, int y0, int width, const std::vector<std::uint32_t>& gids);

/// Fails, before any collider is built, when the cells of the tile layers would make more than
/// kMaxTiledColliders colliders: the sum over cells of their tiles' collision shapes (a lower
/// bound: a concave shape makes several; the builder checks the exact count too).
void check_tile_colliders(Document& doc);

/// A tileset's `objectalignment` value (Tiled 1.4) as TiledTileset::object_anchor:
/// "unspecified" (or absent: "") and "bottomleft" are {0, 1}, "center" {0.5, 0.5}, "topright"
/// {1, 0}, and so on for "topleft", "top", "left", "right", "bottom", "bottomright". Fails naming
/// `file` and `element` for any other word.
Vec2 object_alignment_anchor(std::string_view value, const std::filesystem::path& file, std::string_view element);

/// Fails naming `file` and `element` when a group nests deeper than kMaxTiledGroupDepth.
void check_group_depth(int depth, const std::filesystem::path& file, std::string_view element);

/// A whole number read as a double: fails naming the field unless it is an integer within
/// [lo, hi].
long long whole_or_fail(double value, long long lo, long long hi, const std::filesystem::path& file,
                        std::string_view element, std::string_view field);

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

/// An external tileset file (.tsx XML, or .tsj/.json), with `first_gid` set by the caller; its
/// size is returned in `bytes`. Use external_tileset (cached, charged) rather than this.
[[nodiscard]] TiledTileset read_tileset_file(const std::filesystem::path& file, std::size_t& bytes);
/// A .tsj/.json tileset file (read_tileset_file dispatches here).
[[nodiscard]] TiledTileset read_tileset_json(const std::filesystem::path& file, std::size_t& bytes);

/// A template file: .tx (XML) or .tj (JSON); its size is returned in `bytes`. Use
/// external_template (cached, charged) rather than this.
[[nodiscard]] Template read_template(const std::filesystem::path& file, std::size_t& bytes);
/// A .tj template (read_template dispatches here).
[[nodiscard]] Template read_template_json(const std::filesystem::path& file, std::size_t& bytes);

/// The gid of a template object rewritten for the map: the template's tileset is looked up among
/// the map's tilesets by file (and appended to them when the map does not use it yet). Fails
/// naming the template when its gid is below its tileset's first gid.
[[nodiscard]] std::uint32_t map_template_gid(Document& doc, const Template& t);

/// Both readers check numbers the same way: finite and at most kMaxTiledCoordinate in
/// magnitude, else fail naming the field.
float finite_or_fail(double value, const std::filesystem::path& file, std::string_view element,
                     std::string_view field);

}  // namespace collide::tiled
