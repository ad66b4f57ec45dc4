#pragma once
/// @file
/// Static collision geometry from Tiled maps (https://www.mapeditor.org): `.tmx` (XML) and
/// `.tmj`/`.json` (JSON) maps, with external tilesets (`.tsx` or `.tsj`/`.json`) and object
/// templates (`.tx` or `.tj`) in either format.
///
/// Coordinates. Everything is in Tiled's own map space: pixels, x to the right, **y down**,
/// origin at the map's top-left corner. collide's math does not care which way y points, but the
/// words do: a polygon that collide calls counter-clockwise (positive signed area) looks
/// clockwise on a y-down screen, and a positive rotation (Tiled's `rotation`, degrees clockwise
/// on screen) is a positive angle in these coordinates. Games whose world is y-up can call
/// `flip_y`, which mirrors every collider about the horizontal line y = height / 2.
///
/// What becomes a collider (one `TiledCollider` per convex piece):
///  - rectangle objects -> a box (Polygon); a rectangle of zero width or height -> a Segment;
///  - ellipse objects -> a Circle when width == height, otherwise a convex Polygon of
///    kTiledEllipseVertices vertices on the ellipse (inscribed: it covers slightly less area);
///  - polygon objects -> convex pieces by `decompose_convex` (concave outlines allowed);
///  - polyline objects -> one Segment per link (a chain; zero-length links are skipped);
///  - tile objects and non-empty cells of tile layers -> the collision shapes that the tileset
///    gives the tile (Tiled's collision editor), with the gid's flip bits (horizontal, vertical,
///    diagonal) and the object's scale and rotation applied. A tile object whose tile has no
///    collision shapes becomes a box of its image rectangle if
///    `TiledLoadOptions::tile_object_image_boxes` is set (the default);
///  - point and text objects -> no collider (they are listed in `TiledMap::objects`).
/// Layer offsets and the offsets of nested groups are applied; parallax factors are not (they
/// change drawing only). Hidden layers are loaded too (collision layers are often hidden).
///
/// Which layers collide (`TiledLoadOptions::layers`, `TiledMap::layers` says what was chosen
/// and why). Given layer names (paths, "group/layer"; a group stands for every layer in it),
/// exactly those tile and object layers collide. Otherwise the map's own declarations decide,
/// as game engines read them; each is looked for on the layer, then on its enclosing groups
/// (the nearest wins; names of properties and classes are compared ignoring case):
///  1. a boolean custom property `collides`, `collision` or `collidable` (true: collides, false:
///     skipped; the property Phaser's setCollisionByProperty reads on tiles), or a property
///     `nocollide` of any value (skipped; HaxeFlixel's Tiled demos skip such tile layers);
///  2. else a class (Tiled >= 1.9) of "collision", "collisions" or "solid", or a layer or group
///     name that contains "collision" (melonJS's rule: an object group whose name contains
///     "collision" is the world's static geometry; tutorials name it "Collision(s)").
/// If some layer is declared a collision layer by 1 or 2, only the declared layers collide (the
/// others hold art, spawn points and entities). If none is, every tile and object layer
/// collides except those that property 1 turns off: a map that declares nothing loads as it
/// always did. Image layers never collide. Layers are told apart by their paths.
/// Images are never opened, so missing images are fine. The XML parser never fetches the
/// external DTD that old maps name in their DOCTYPE.
///
/// Supported: orthogonal maps, finite or infinite (chunked) tile layers, tile data as csv,
/// base64, base64 + zlib, gzip or zstd, and legacy `<tile gid>` elements; every version of the
/// formats Tiled has written, from 0.x maps without object ids to JSON before 1.2 (tilesets whose
/// `tiles` is an object keyed by tile id) and 1.9's `class` (docs/tiled-formats.md).
/// Rejected with InvalidInput: isometric, staggered, hexagonal and oblique maps, and input past
/// the limits below (docs/limits.md).

#include <collide/core/transform.hpp>
#include <collide/shape/shape2d.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace collide {

/// Vertices of the convex polygon that stands in for a non-circular Tiled ellipse.
inline constexpr int kTiledEllipseVertices = 16;

/// The gid bits Tiled uses for flips (https://doc.mapeditor.org/en/stable/reference/global-tile-ids/).
inline constexpr std::uint32_t kTiledFlipHorizontal = 0x80000000u;
inline constexpr std::uint32_t kTiledFlipVertical = 0x40000000u;
inline constexpr std::uint32_t kTiledFlipDiagonal = 0x20000000u;
inline constexpr std::uint32_t kTiledRotateHexagonal120 = 0x10000000u;
/// The gid without its flip bits.
inline constexpr std::uint32_t kTiledGidMask = 0x0fffffffu;

// Limits of `load_tiled_map` (docs/limits.md). Each refuses a file that goes past it with
// InvalidInput naming the file, the element, the limit and the value found.

/// Deepest nesting of group layers (`<group>`, JSON "group"); the map's top level is depth 0.
/// Deeper maps are refused before the recursion could overflow the stack.
inline constexpr int kMaxTiledGroupDepth = 64;
/// Most tiles a map may declare: width x height summed over every tile layer and chunk, checked
/// before any tile data is decoded or memory reserved (a 4096 x 4096 map has 16,777,216).
inline constexpr std::uint64_t kMaxTiledMapTiles = std::uint64_t{1} << 24;
/// Most colliders one map may produce (each is about 1.3 KB).
inline constexpr std::size_t kMaxTiledColliders = std::size_t{1} << 20;
/// Most points of one polygon object (convex decomposition is O(n^2) typical, O(n^3) worst).
inline constexpr std::size_t kMaxTiledPolygonPoints = 1024;
/// Largest magnitude of a number in a map, tileset or template (coordinates, sizes, offsets,
/// points, rotation), pixels or degrees: far beyond any map, and small enough that every
/// collider built from it is finite.
inline constexpr double kMaxTiledCoordinate = 1.0e7;
/// Most bytes one load reads: the map plus every use of an external tileset or template (a file
/// used twice counts twice, as a copy of it is kept each time).
inline constexpr std::size_t kMaxTiledLoadBytes = std::size_t{256} << 20;

/// What a Tiled object is.
enum class TiledShapeKind : unsigned char { rectangle, ellipse, polygon, polyline, point, text, tile };

/// Lower-case name of the kind ("rectangle", ..., "tile").
[[nodiscard]] const char* to_string(TiledShapeKind kind) noexcept;

/// A Tiled object as the file describes it, templates merged. Map pixels, y down.
struct TiledObject {
  int id = 0;                 ///< Tiled's object id (0 inside tilesets when absent)
  std::string name;           ///< `name`
  std::string type;           ///< `type` (Tiled < 1.9) or `class` (Tiled >= 1.9)
  TiledShapeKind kind = TiledShapeKind::rectangle;
  Vec2 position{0.0f, 0.0f};  ///< x, y in the layer's frame; a tile object's bottom-left corner
  Vec2 size{0.0f, 0.0f};      ///< width, height (pixels); zero when the file gives none
  float rotation = 0.0f;      ///< radians about `position`, positive = clockwise on screen
  std::vector<Vec2> points;   ///< polygon/polyline points relative to `position`
  std::uint32_t gid = 0;      ///< tile objects: global tile id with flip bits; otherwise 0
  std::string layer;          ///< layer path, groups joined by '/' ("Collision", "g/objects")
  Vec2 layer_offset{0.0f, 0.0f};  ///< summed offsets of the layer and its groups
  std::string template_file;  ///< the `.tx` it was instantiated from, empty if none
};

/// What a Tiled layer is.
enum class TiledLayerKind : unsigned char { tile, object, image, group };

/// "tile layer", "object layer", "image layer" or "group".
[[nodiscard]] const char* to_string(TiledLayerKind kind) noexcept;

/// A custom property as the file writes it.
struct TiledProperty {
  std::string name;
  std::string type;   ///< "string" (also when the file names no type), "bool", "int", "float", ...
  std::string value;  ///< as text: "true"/"false" for bools, numbers as written; empty for classes
};

/// A layer of the map (groups included), as the file describes it, and whether it collides.
struct TiledLayer {
  std::string name;                      ///< path, groups joined by '/' (as TiledObject::layer)
  TiledLayerKind kind = TiledLayerKind::object;
  std::string type;                      ///< `class` (Tiled >= 1.9); empty when none
  std::vector<TiledProperty> properties; ///< the layer's custom properties, in file order
  int parent = -1;                       ///< index in TiledMap::layers of its group, -1 at the top
  // Filled by load_tiled_map (the file comment gives the rule):
  bool collides = false;  ///< its objects and cells became colliders (never for groups)
  std::string reason;     ///< why it collides or not ("class 'solid'", "not named in layers", ...)
  int objects = 0;        ///< objects of an object layer
  int cells = 0;          ///< non-empty cells of a tile layer
  int colliders = 0;      ///< colliders built from it (0 when skipped)
};

/// One tile of a tileset that carries collision shapes or its own image size.
struct TiledTile {
  int id = 0;                       ///< local tile id within the tileset
  Vec2 image_size{0.0f, 0.0f};      ///< per-tile image size (image collections), else tile size
  std::vector<TiledObject> collision;  ///< collision shapes in the tile's pixels, y down
};

/// A tileset, embedded or external.
struct TiledTileset {
  std::string name;
  std::uint32_t first_gid = 1;    ///< gid of local tile 0 in the map that uses it
  int tile_count = 0;             ///< `tilecount`
  Vec2 tile_size{0.0f, 0.0f};     ///< `tilewidth`, `tileheight`
  Vec2 tile_offset{0.0f, 0.0f};   ///< `<tileoffset>`: drawing offset of every tile
  /// `objectalignment` (Tiled 1.4): the point of a tile object's rectangle that sits on the
  /// object's position (and that it rotates about), as fractions of the rectangle's size from
  /// its top-left corner, y down. {0, 1}, bottom-left, when unspecified (orthogonal maps).
  Vec2 object_anchor{0.0f, 1.0f};
  std::filesystem::path source;   ///< the `.tsx`/`.tsj` file, empty when embedded
  std::vector<TiledTile> tiles;   ///< only tiles with collision shapes or their own image, by id

  /// The tile with local id `id`, or nullptr. Binary search: `tiles` must be sorted by id (as
  /// load_tiled_map leaves it).
  [[nodiscard]] const TiledTile* find(int id) const noexcept;
};

/// Where a collider came from: for error messages, picking and game logic.
struct TiledSource {
  std::string layer;            ///< layer path ("group/layer")
  int object_id = 0;            ///< Tiled object id; 0 for a tile-layer cell
  std::string name;             ///< object name
  std::string type;             ///< object type/class
  TiledShapeKind kind = TiledShapeKind::rectangle;  ///< the object's kind (tile for cells)
  bool from_tile = false;       ///< true: a collision shape of a tile (cell or tile object)
  int tile_shape_id = 0;        ///< from_tile: id of the collision object inside the tile
  std::uint32_t gid = 0;        ///< tile gid with flip bits, 0 when not from a tile
  int cell_x = -1;              ///< tile-layer cell column, -1 otherwise
  int cell_y = -1;              ///< tile-layer cell row, -1 otherwise
};

/// One convex piece of static geometry: `shape` in local space, placed by `transform`.
struct TiledCollider {
  Shape2D shape;
  Transform transform;  ///< local -> map pixels (y down)
  TiledSource source;
};

/// A loaded map: its header, its tilesets and objects as the file describes them, and the
/// static colliders built from them.
struct TiledMap {
  std::filesystem::path path;
  std::string orientation;           ///< always "orthogonal" (others are rejected)
  int width = 0;                     ///< in tiles (finite maps)
  int height = 0;                    ///< in tiles (finite maps)
  Vec2 tile_size{0.0f, 0.0f};        ///< map tile size, pixels
  bool infinite = false;             ///< chunked tile layers
  std::vector<TiledTileset> tilesets;  ///< by first gid (as Tiled writes them)
  std::vector<TiledLayer> layers;    ///< every layer in file order, a group before its layers
  std::vector<TiledObject> objects;  ///< every object of every object layer, in file order
  int tile_cells = 0;                ///< non-empty tile-layer cells
  std::vector<TiledCollider> colliders;
};

/// Options of `load_tiled_map`.
struct TiledLoadOptions {
  /// A tile object whose tile has no collision shapes becomes a box of its image rectangle.
  bool tile_object_image_boxes = true;
  /// The tile and object layers that collide, by path ("ground", "group/walls"; a group's path
  /// names every layer in it). Empty: the map's declarations decide (see the file comment).
  /// A name that is no layer of the map is an InvalidInput that lists the map's layers.
  std::vector<std::string> layers;
};

/// Loads a `.tmx` or `.tmj`/`.json` map and builds its static colliders (see the file comment
/// for what becomes what). External tilesets and templates resolve relative to the file that
/// names them. Throws InvalidInput naming the file and the element when a file cannot be read
/// or parsed, an attribute is missing or not a number, a polygon is self-intersecting or
/// degenerate, a gid names no tileset, tile data does not decode to width x height gids, or
/// the map is not orthogonal. A syntax error names the line, the column and the element it is
/// in: the XML elements open there ("inside <map> > <objectgroup name=Walls> > <object id=7>")
/// or the JSON path ("in layers[0].objects[1] (id=9).polygon[0]"). An error in an external
/// tileset or template names that file, after the map and the element that refers to it.
/// Input past a limit is refused naming the limit and the value: files over kMaxInputFileBytes
/// (64 MiB; /dev/zero too), groups nested deeper than kMaxTiledGroupDepth, JSON nested deeper
/// than kMaxJsonDepth, more than kMaxTiledMapTiles declared tiles, cells beyond int range,
/// firstgid outside [1, kTiledGidMask], numbers beyond kMaxTiledCoordinate, polygons over
/// kMaxTiledPolygonPoints, more than kMaxTiledColliders colliders or kMaxTiledLoadBytes read.
/// Throws InvalidInput "<file>: layers: 'NAME' is no layer of the map (its layers: ...)" for a
/// name in `options.layers` that no layer has. Messages are valid UTF-8 (other bytes quoted as \xNN). Allocates; load time only.
[[nodiscard]] TiledMap load_tiled_map(const std::filesystem::path& path,
                                      const TiledLoadOptions& options = {});

/// True when `path` holds a JSON object with a string "type" member, as Tiled's JSON maps
/// ("map"), tilesets and templates have: how `collide run` tells a Tiled `.json` map from a scene
/// JSON file (docs/scene-json.md), which has no "type". False for a file that cannot be read or
/// is not valid JSON (the caller's loader then reports why). Reads and parses the whole file.
[[nodiscard]] bool looks_like_tiled_json(const std::filesystem::path& path);

/// Mirrors every collider of `map` about y = height_pixels / 2 (map height in pixels for finite
/// maps), for games whose world is y-up: a point (x, y) moves to (x, height_pixels - y),
/// rotations change sign, polygons are re-wound counter-clockwise. `objects` are left as the
/// file describes them. Throws InvalidInput if height_pixels is not finite.
void flip_y(TiledMap& map, float height_pixels);

}  // namespace collide
