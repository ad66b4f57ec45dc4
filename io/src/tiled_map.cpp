// Tiled map -> colliders: object shapes, tile collision shapes with flips, offsets.

#include "text_file.hpp"
#include "tiled_document.hpp"

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/decompose/convex_decomposition.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <numbers>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace collide {

const char* to_string(TiledShapeKind kind) noexcept {
  switch (kind) {
    case TiledShapeKind::rectangle: return "rectangle";
    case TiledShapeKind::ellipse: return "ellipse";
    case TiledShapeKind::polygon: return "polygon";
    case TiledShapeKind::polyline: return "polyline";
    case TiledShapeKind::point: return "point";
    case TiledShapeKind::text: return "text";
    case TiledShapeKind::tile: return "tile";
  }
  return "unknown";
}

const char* to_string(TiledLayerKind kind) noexcept {
  switch (kind) {
    case TiledLayerKind::tile: return "tile layer";
    case TiledLayerKind::object: return "object layer";
    case TiledLayerKind::image: return "image layer";
    case TiledLayerKind::group: return "group";
  }
  return "unknown";
}

const TiledTile* TiledTileset::find(int id) const noexcept {
  // Binary search: the readers sort `tiles` by id (a map's cells may name many distinct tiles).
  const auto it = std::lower_bound(tiles.begin(), tiles.end(), id,
                                   [](const TiledTile& t, int key) { return t.id < key; });
  return it != tiles.end() && it->id == id ? &*it : nullptr;
}

namespace tiled {

void fail(const std::filesystem::path& file, std::string_view element, std::string_view message) {
  throw InvalidInput(file.generic_string() + ": " + std::string(element) + ": " +
                     std::string(message));
}

float finite_or_fail(double value, const std::filesystem::path& file, std::string_view element,
                     std::string_view field) {
  if (!std::isfinite(value)) fail(file, element, std::string(field) + ": not a finite number");
  if (std::fabs(value) > kMaxTiledCoordinate) {
    std::ostringstream shown;
    shown << std::setprecision(9) << value;
    fail(file, element, std::string(field) + ": " + shown.str() + " is beyond +-1e7 (the limit, kMaxTiledCoordinate)");
  }
  return static_cast<float>(value);
}

std::uint32_t map_template_gid(Document& doc, const Template& t) {
  TiledMap& map = doc.map;
  const std::uint32_t flips = t.object.gid & ~kTiledGidMask;
  if ((t.object.gid & kTiledGidMask) < t.tileset_first_gid) {
    fail(t.object.template_file, "<object>", "gid " + std::to_string(t.object.gid & kTiledGidMask) +
                                                 " is below its tileset's firstgid " +
                                                 std::to_string(t.tileset_first_gid));
  }
  const std::uint32_t local = (t.object.gid & kTiledGidMask) - t.tileset_first_gid;
  // Where the map put the template's tileset, found once per tileset file and load (resolving
  // paths for every object and tileset would be slow for maps of many of both).
  const std::string key = t.tileset_source.lexically_normal().generic_string();
  if (const auto known = doc.template_tilesets.find(key); known != doc.template_tilesets.end()) {
    return (known->second + local) | flips;
  }
  // weakly_canonical without an error code throws on a name the file system refuses (a component
  // longer than NAME_MAX, found by fuzz_tiled_tx); such a path is compared as written and fails
  // later, when read, with the file's name.
  const auto canonical = [](const std::filesystem::path& p) {
    std::error_code ec;
    std::filesystem::path c = std::filesystem::weakly_canonical(p, ec);
    return ec ? p.lexically_normal() : c;
  };
  const std::filesystem::path want = canonical(t.tileset_source);
  for (const TiledTileset& ts : map.tilesets) {
    if (!ts.source.empty() && canonical(ts.source) == want) {
      doc.template_tilesets.emplace(key, ts.first_gid);
      return (ts.first_gid + local) | flips;
    }
  }
  // The map does not list the template's tileset: give it gids after the last tileset's. First
  // gids are at most kTiledGidMask and tile ids and counts at most INT_MAX, so 64 bits hold it.
  std::uint64_t next = 1;
  for (const TiledTileset& ts : map.tilesets) {
    next = std::max<std::uint64_t>(next, std::uint64_t{ts.first_gid} + static_cast<std::uint64_t>(std::max(ts.tile_count, 1)));
    for (const TiledTile& tile : ts.tiles) {
      next = std::max<std::uint64_t>(next, std::uint64_t{ts.first_gid} + static_cast<std::uint64_t>(tile.id) + 1);
    }
  }
  if (next + local > kTiledGidMask) {
    fail(t.object.template_file, "<object>", "no gid left for its tileset in the map (gids end at " +
                                                 std::to_string(kTiledGidMask) + ")");
  }
  TiledTileset ts = external_tileset(doc, t.tileset_source);
  ts.first_gid = static_cast<std::uint32_t>(next);
  doc.template_tilesets.emplace(key, ts.first_gid);
  map.tilesets.push_back(std::move(ts));
  return (static_cast<std::uint32_t>(next) + local) | flips;
}

}  // namespace tiled

namespace {

/// A 2D affine map p -> m * p + t. Tile flips and tile-object scaling are not rigid, so they
/// are applied to vertices; only the rigid rest goes into the collider's Transform.
struct Affine {
  Vec2 col0{1.0f, 0.0f};
  Vec2 col1{0.0f, 1.0f};
  Vec2 t{0.0f, 0.0f};

  [[nodiscard]] Vec2 apply(Vec2 p) const noexcept { return col0 * p.x + col1 * p.y + t; }
  /// this after `inner`: p -> this(inner(p)).
  [[nodiscard]] Affine after(const Affine& inner) const noexcept {
    return {col0 * inner.col0.x + col1 * inner.col0.y, col0 * inner.col1.x + col1 * inner.col1.y,
            apply(inner.t)};
  }
  /// Uniform scale when the map is a similarity (rotation/mirror times a scale), else -1.
  [[nodiscard]] float similarity_scale() const noexcept {
    const float a = length(col0);
    const float b = length(col1);
    const float tol = kRelativeTolerance * std::max(a, b);
    return std::fabs(a - b) <= tol && std::fabs(dot(col0, col1)) <= tol * std::max(a, b) ? a : -1.0f;
  }
};

Affine rigid(Vec2 position, float radians) {
  const Rot2 q = Rot2::from_angle(radians);
  return {{q.c, q.s}, {-q.s, q.c}, position};
}

/// The flips of a gid as a map of tile pixels [0, w] x [0, h] onto the flipped tile, y down.
/// Tiled applies the diagonal flip (swap x and y) first, then horizontal, then vertical.
Affine tile_flips(std::uint32_t gid, Vec2 size) {
  Affine a;
  Vec2 s = size;
  if (gid & kTiledFlipDiagonal) {
    a = {{0.0f, 1.0f}, {1.0f, 0.0f}, {0.0f, 0.0f}};
    s = {size.y, size.x};
  }
  if (gid & kTiledFlipHorizontal) a = Affine{{-1.0f, 0.0f}, {0.0f, 1.0f}, {s.x, 0.0f}}.after(a);
  if (gid & kTiledFlipVertical) a = Affine{{1.0f, 0.0f}, {0.0f, -1.0f}, {0.0f, s.y}}.after(a);
  return a;
}

/// Fails when a map that has `count` colliders would get one more than kMaxTiledColliders.
void check_collider_count(const TiledMap& map, std::size_t count) {
  if (count >= kMaxTiledColliders) {
    tiled::fail(map.path, "map", "more than " + std::to_string(kMaxTiledColliders) +
                                     " colliders (the limit, kMaxTiledColliders)");
  }
}

/// Appends the colliders of one object's own shape, mapped by `local` (object frame -> collider
/// frame), placed by `xf`.
class Builder {
 public:
  Builder(const TiledMap& map, std::vector<TiledCollider>& out) : map_(map), out_(out) {}

  void shape(const TiledObject& obj, const Affine& local, const Transform& xf,
             const TiledSource& source, const std::string& label) {
    const float w = obj.size.x;
    const float h = obj.size.y;
    auto add = [&](Shape2D s) {
      check_collider_count(map_, out_.size());
      out_.push_back({std::move(s), xf, source});
    };
    auto outline = [&](const std::vector<Vec2>& pts, bool convex) {
      std::vector<Vec2> mapped;
      for (Vec2 p : pts) mapped.push_back(local.apply(p));
      try {
        if (convex) {
          add(make_polygon(mapped));
        } else {
          for (Polygon& piece : decompose_convex(mapped, label)) add(std::move(piece));
        }
      } catch (const InvalidInput& e) {
        const std::string what = e.what();
        throw InvalidInput(what.rfind(label, 0) == 0 ? what : label + ": " + what);
      }
    };
    auto chain = [&](const std::vector<Vec2>& pts) {
      for (size_t i = 0; i + 1 < pts.size(); ++i) {
        const Vec2 a = local.apply(pts[i]);
        const Vec2 b = local.apply(pts[i + 1]);
        if (distance_squared(a, b) > 0.0f) add(make_segment(a, b));
      }
    };
    switch (obj.kind) {
      case TiledShapeKind::rectangle:
        if (w > 0.0f && h > 0.0f) {
          outline({{0.0f, 0.0f}, {w, 0.0f}, {w, h}, {0.0f, h}}, true);
        } else if (w > 0.0f || h > 0.0f) {
          chain({{0.0f, 0.0f}, {w, h}});  // a rectangle of zero width or height is a segment
        }
        break;
      case TiledShapeKind::ellipse: {
        if (!(w > 0.0f && h > 0.0f)) {
          if (w > 0.0f || h > 0.0f) chain({{0.0f, 0.0f}, {w, h}});
          break;
        }
        const float scale = local.similarity_scale();
        if (w == h && scale > 0.0f) {
          add(make_circle(local.apply({0.5f * w, 0.5f * h}), 0.5f * w * scale));
          break;
        }
        std::vector<Vec2> pts;
        for (int i = 0; i < kTiledEllipseVertices; ++i) {
          const float a = 2.0f * std::numbers::pi_v<float> * static_cast<float>(i) /
                          static_cast<float>(kTiledEllipseVertices);
          pts.push_back({0.5f * w * (1.0f + std::cos(a)), 0.5f * h * (1.0f + std::sin(a))});
        }
        outline(pts, true);
        break;
      }
      case TiledShapeKind::polygon: outline(obj.points, false); break;
      case TiledShapeKind::polyline: chain(obj.points); break;
      case TiledShapeKind::point:
      case TiledShapeKind::text:
      case TiledShapeKind::tile: break;
    }
  }

  /// The tileset holding `gid` and the tile's local id, or nullptr when no tileset has it: the
  /// local id must be below `tilecount` (when known) or name a tile the tileset lists.
  const TiledTileset* tileset_of(std::uint32_t gid, int& local) const {
    const std::uint32_t id = gid & kTiledGidMask;
    const TiledTileset* best = tiled::tileset_with_gid(map_, id);
    if (best == nullptr) return nullptr;
    local = static_cast<int>(id - best->first_gid);
    const bool listed = best->tile_count <= 0 || local < best->tile_count || best->find(local);
    return listed ? best : nullptr;
  }

 private:
  const TiledMap& map_;
  std::vector<TiledCollider>& out_;
};

std::string object_label(const TiledMap& map, const TiledObject& obj) {
  return map.path.generic_string() + ": <object id=" + std::to_string(obj.id) + "> in layer '" +
         obj.layer + "'";
}

// Which layers collide: the rule of the file comment in tiled.hpp.

/// Custom properties that say whether a layer collides (boolean), and the one that says it
/// does not whatever its value (HaxeFlixel's `nocollide`).
constexpr std::array<std::string_view, 3> kCollidesProperties = {"collides", "collision", "collidable"};
constexpr std::string_view kNoCollideProperty = "nocollide";
/// Classes that declare a collision layer, and the word a collision layer's name contains.
constexpr std::array<std::string_view, 3> kCollisionClasses = {"collision", "collisions", "solid"};
constexpr std::string_view kCollisionNameWord = "collision";

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// A say about whether a layer collides, found on the layer (`at` is itself) or inherited from
/// the group `at`.
struct Say {
  bool collides = false;
  std::string why;  ///< "property collides=false", "class 'solid'", ...
  std::size_t at = 0;
};

/// The reason for layer `i`: the say, and the group it was found on when that is not `i`.
std::string reason(const std::vector<TiledLayer>& layers, const Say& say, std::size_t i) {
  return say.at == i ? say.why : say.why + " on group '" + layers[say.at].name + "'";
}

/// Part 1 of the rule on one layer's own properties, or nothing.
std::optional<Say> own_property_say(const TiledLayer& layer, std::size_t i) {
  for (const TiledProperty& p : layer.properties) {
    const std::string name = lower(p.name);
    if (name == kNoCollideProperty) return Say{false, "property " + p.name, i};
    const std::string value = lower(p.value);
    if (std::find(kCollidesProperties.begin(), kCollidesProperties.end(), name) != kCollidesProperties.end() &&
        (value == "true" || value == "false")) {
      return Say{value == "true", "property " + p.name + "=" + value, i};
    }
  }
  return std::nullopt;
}

/// Part 2 of the rule on one layer's own class and name (its own part of the path), or nothing.
std::optional<Say> own_declaration(const std::vector<TiledLayer>& layers, const TiledLayer& layer, std::size_t i) {
  if (std::find(kCollisionClasses.begin(), kCollisionClasses.end(), lower(layer.type)) != kCollisionClasses.end()) {
    return Say{true, "class '" + layer.type + "'", i};
  }
  const std::size_t group_path = layer.parent >= 0 ? layers[static_cast<std::size_t>(layer.parent)].name.size() + 1 : 0;
  if (lower(layer.name.substr(std::min(group_path, layer.name.size()))).find(kCollisionNameWord) != std::string::npos) {
    return Say{true, "name contains '" + std::string(kCollisionNameWord) + "'", i};
  }
  return std::nullopt;
}

/// Sets `collides` and `reason` of every layer of `map`. Groups come before their layers, so
/// one pass in file order inherits what a group says: linear in the number of layers.
void select_layers(TiledMap& map, const TiledLoadOptions& options) {
  std::vector<TiledLayer>& layers = map.layers;
  const auto parent = [&](std::size_t i) { return static_cast<std::size_t>(layers[i].parent); };
  if (!options.layers.empty()) {
    const std::unordered_set<std::string> wanted(options.layers.begin(), options.layers.end());
    std::unordered_set<std::string> present;
    for (const TiledLayer& l : layers) present.insert(l.name);
    for (const std::string& want : options.layers) {
      if (present.count(want) != 0) continue;
      std::string list;
      for (const TiledLayer& l : layers) list += (list.empty() ? "'" : ", '") + l.name + "'";
      tiled::fail(map.path, "layers", "'" + want + "' is no layer of the map (its layers: " +
                                          (list.empty() ? std::string("none") : list) + ")");
    }
    for (std::size_t i = 0; i < layers.size(); ++i) {  // named itself, or inside a named group
      layers[i].collides = wanted.count(layers[i].name) != 0 || (layers[i].parent >= 0 && layers[parent(i)].collides);
      layers[i].reason = layers[i].collides ? "named in layers" : "not named in layers";
    }
  } else {
    std::vector<std::optional<Say>> say(layers.size());       // part 1, the nearest wins
    std::vector<std::optional<Say>> declared(layers.size());  // part 2, the nearest wins
    for (std::size_t i = 0; i < layers.size(); ++i) {
      say[i] = own_property_say(layers[i], i);
      if (!say[i] && layers[i].parent >= 0) say[i] = say[parent(i)];
      declared[i] = own_declaration(layers, layers[i], i);
      if (!declared[i] && layers[i].parent >= 0) declared[i] = declared[parent(i)];
    }
    std::string declared_names;
    const auto collision_layer = [&](std::size_t i) {
      return (layers[i].kind == TiledLayerKind::tile || layers[i].kind == TiledLayerKind::object) &&
             (say[i] ? say[i]->collides : declared[i].has_value());
    };
    for (std::size_t i = 0; i < layers.size(); ++i) {
      if (collision_layer(i)) declared_names += (declared_names.empty() ? "'" : ", '") + layers[i].name + "'";
    }
    for (std::size_t i = 0; i < layers.size(); ++i) {
      TiledLayer& l = layers[i];
      if (say[i]) {
        l.collides = say[i]->collides;
        l.reason = reason(layers, *say[i], i);
      } else if (declared[i]) {
        l.collides = true;
        l.reason = reason(layers, *declared[i], i);
      } else if (declared_names.empty()) {
        l.collides = true;
        l.reason = "the map declares no collision layer, so every layer collides";
      } else {
        l.collides = false;
        l.reason = "not declared a collision layer (the map declares " + declared_names + ")";
      }
    }
  }
  for (TiledLayer& l : layers) {
    if (l.kind == TiledLayerKind::image) {
      l.collides = false;
      l.reason = "an image layer has no shapes";
    } else if (l.kind == TiledLayerKind::group) {
      l.collides = false;
      l.reason = "a group: its layers are listed on their own";
    }
  }
}

void build_colliders(TiledMap& map, const std::vector<tiled::TileLayer>& layers,
                     const TiledLoadOptions& options) {
  select_layers(map, options);
  std::unordered_map<std::string, bool> collides;  // by layer path: any layer of that path
  for (const TiledLayer& l : map.layers) collides[l.name] = collides[l.name] || (l.collides && l.kind != TiledLayerKind::group);
  Builder builder(map, map.colliders);
  for (const TiledObject& obj : map.objects) {
    if (!collides[obj.layer]) continue;
    const Transform xf = Transform::from(obj.layer_offset + obj.position, obj.rotation);
    const std::string label = object_label(map, obj);
    TiledSource source{obj.layer, obj.id, obj.name, obj.type, obj.kind, false, 0, 0, -1, -1};
    if (obj.kind != TiledShapeKind::tile) {
      builder.shape(obj, Affine{}, xf, source, label);
      continue;
    }
    int local = 0;
    const TiledTileset* ts = builder.tileset_of(obj.gid, local);
    if (ts == nullptr) {
      tiled::fail(map.path, "<object id=" + std::to_string(obj.id) + ">",
                  "gid " + std::to_string(obj.gid & kTiledGidMask) + " is in no tileset");
    }
    const TiledTile* tile = ts->find(local);
    const Vec2 image = tile != nullptr ? tile->image_size : ts->tile_size;
    const Vec2 size{obj.size.x > 0.0f ? obj.size.x : image.x, obj.size.y > 0.0f ? obj.size.y : image.y};
    source.gid = obj.gid;
    source.from_tile = true;
    // Tile pixels -> object frame: flip in the tile, scale to the object's size, and move the
    // tileset's anchor point of the object's rectangle (objectalignment; bottom-left unless
    // set) onto the object's position, which it rotates about.
    const bool diagonal = (obj.gid & kTiledFlipDiagonal) != 0;
    const Vec2 flipped = diagonal ? Vec2{image.y, image.x} : image;
    const Vec2 top_left = -ts->object_anchor * size;
    const Affine scale{{size.x / flipped.x, 0.0f}, {0.0f, size.y / flipped.y}, top_left + ts->tile_offset};
    const Affine tile_to_object = scale.after(tile_flips(obj.gid, image));
    if (tile == nullptr || tile->collision.empty()) {
      if (options.tile_object_image_boxes && size.x > 0.0f && size.y > 0.0f) {
        source.from_tile = false;
        TiledObject box = obj;
        box.kind = TiledShapeKind::rectangle;
        box.size = size;
        builder.shape(box, Affine{{1.0f, 0.0f}, {0.0f, 1.0f}, top_left}, xf, source, label);
      }
      continue;
    }
    for (const TiledObject& part : tile->collision) {
      source.tile_shape_id = part.id;
      const Affine local_map = tile_to_object.after(rigid(part.position, part.rotation));
      builder.shape(part, local_map, xf, source,
                    label + " tile shape <object id=" + std::to_string(part.id) + ">");
    }
  }

  // Tile layers: the shapes of a gid (flips included) are built once and placed per cell.
  std::unordered_map<std::uint32_t, std::vector<TiledCollider>> by_gid;
  for (const tiled::TileLayer& layer : layers) {
    if (!collides[layer.name]) continue;
    for (const tiled::Cell& cell : layer.cells) {
      int local = 0;
      const TiledTileset* ts = builder.tileset_of(cell.gid, local);
      if (ts == nullptr) {
        tiled::fail(map.path, "<layer name=" + layer.name + ">",
                    "cell (" + std::to_string(cell.x) + ", " + std::to_string(cell.y) + "): gid " +
                        std::to_string(cell.gid & kTiledGidMask) + " is in no tileset");
      }
      const TiledTile* tile = ts->find(local);
      if (tile == nullptr || tile->collision.empty()) continue;
      auto it = by_gid.find(cell.gid);
      if (it == by_gid.end()) {
        std::vector<TiledCollider> shapes;
        Builder local_builder(map, shapes);
        const Affine flips = tile_flips(cell.gid, tile->image_size);
        for (const TiledObject& part : tile->collision) {
          TiledSource source{layer.name, 0, part.name, part.type, TiledShapeKind::tile, true,
                             part.id, cell.gid, -1, -1};
          local_builder.shape(part, flips.after(rigid(part.position, part.rotation)), Transform{},
                              source,
                              map.path.generic_string() + ": tileset '" + ts->name + "' <tile id=" +
                                  std::to_string(local) + "> <object id=" + std::to_string(part.id) + ">");
        }
        it = by_gid.emplace(cell.gid, std::move(shapes)).first;
      }
      // Orthogonal maps draw a tile with its bottom-left corner on the cell's bottom-left.
      const bool diagonal = (cell.gid & kTiledFlipDiagonal) != 0;
      const float tile_h = diagonal ? tile->image_size.x : tile->image_size.y;
      const Vec2 top_left = layer.offset + ts->tile_offset +
                            Vec2{static_cast<float>(cell.x) * map.tile_size.x,
                                 static_cast<float>(cell.y + 1) * map.tile_size.y - tile_h};
      for (const TiledCollider& c : it->second) {
        TiledCollider placed = c;
        placed.transform = Transform{top_left, Rot2{}};
        placed.source.cell_x = cell.x;
        placed.source.cell_y = cell.y;
        check_collider_count(map, map.colliders.size());
        map.colliders.push_back(std::move(placed));
      }
    }
  }
}

}  // namespace

TiledMap load_tiled_map(const std::filesystem::path& path, const TiledLoadOptions& options) {
  try {
    const std::string ext = path.extension().string();
    tiled::Document doc = (ext == ".tmj" || ext == ".json") ? tiled::read_tmj(path)
                                                           : tiled::read_tmx(path);
    build_colliders(doc.map, doc.tile_layers, options);
    // What each layer held and gave, for the caller's summary (layers are told apart by path).
    std::unordered_map<std::string, int> objects, cells, colliders;
    for (const TiledObject& o : doc.map.objects) ++objects[o.layer];
    for (const tiled::TileLayer& t : doc.tile_layers) cells[t.name] += static_cast<int>(t.cells.size());
    for (const TiledCollider& c : doc.map.colliders) ++colliders[c.source.layer];
    for (TiledLayer& l : doc.map.layers) {
      if (l.kind == TiledLayerKind::object) l.objects = objects[l.name];
      if (l.kind == TiledLayerKind::tile) l.cells = cells[l.name];
      if (l.collides) l.colliders = colliders[l.name];
    }
    return std::move(doc.map);
  } catch (const InvalidInput& e) {
    // Messages quote names and values from the files: bytes that are not UTF-8 become \xNN.
    throw InvalidInput(io::valid_utf8(e.what()));
  }
}

void flip_y(TiledMap& map, float height_pixels) {
  if (!std::isfinite(height_pixels)) throw InvalidInput("flip_y height_pixels: not finite");
  auto mirror = [](Vec2 v) { return Vec2{v.x, -v.y}; };
  for (TiledCollider& c : map.colliders) {
    c.transform.p = {c.transform.p.x, height_pixels - c.transform.p.y};
    c.transform.q.s = -c.transform.q.s;
    std::visit(
        [&](auto& s) {
          using T = std::decay_t<decltype(s)>;
          if constexpr (std::is_same_v<T, Circle>) {
            s.center = mirror(s.center);
          } else if constexpr (std::is_same_v<T, Segment>) {
            s = Segment{mirror(s.b), mirror(s.a)};  // swapped: edge 0 keeps facing the same way
          } else if constexpr (std::is_same_v<T, Capsule>) {
            s.a = mirror(s.a);
            s.b = mirror(s.b);
          } else {
            std::vector<Vec2> v;
            for (int i = s.count - 1; i >= 0; --i) v.push_back(mirror(s.vertices[i]));
            s = make_convex_polygon(v, s.radius);
          }
        },
        c.shape);
  }
}

}  // namespace collide
