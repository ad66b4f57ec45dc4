// The JSON side of Tiled: .tmj/.json maps (nlohmann_json). External tilesets and templates may
// be XML (.tsx/.tx); they go through the XML reader. Every format Tiled has written reads
// (docs/tiled-formats.md): before 1.2 a tileset's "tiles" is an object keyed by tile id, and
// before 1.0 a map has no "type".
//
// Members are read through references (find_member, array_member), never copied: a copy of a
// group layer would copy everything under it, at every level (quadratic time in the nesting).

#include "json_syntax.hpp"
#include "text_file.hpp"
#include "tiled_document.hpp"

#include <collide/core/error.hpp>
#include <collide/io/shape_json.hpp>

#include <nlohmann/json.hpp>

#include <charconv>
#include <climits>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace collide::tiled {
namespace {

using Json = nlohmann::json;

/// Reading context: the file and a path to the element ("layers[2].objects[5] (id=12)").
struct Where {
  const std::filesystem::path& file;
  std::string element;

  [[nodiscard]] Where item(const std::string& key, size_t i, const Json& j) const {
    std::string e = element.empty() ? key : element + "." + key;
    e.append("[").append(std::to_string(i)).append("]");
    if (j.is_object()) {
      const auto id = j.find("id");
      if (id != j.end() && id->is_number_integer()) e.append(" (id=").append(id->dump()).append(")");
    }
    return {file, e};
  }
  [[noreturn]] void fail(std::string_view message) const {
    tiled::fail(file, element.empty() ? "root" : element, message);
  }
};

/// The member `key` of `j`, or null when `j` is not an object or has no such member.
const Json* find_member(const Json& j, const char* key) {
  if (!j.is_object()) return nullptr;
  const auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

/// The array member `key` of `j`: an empty array when absent; fails when it is not an array.
const Json& array_member(const Json& j, const char* key, const Where& w) {
  static const Json kEmpty = Json::array();
  const Json* v = find_member(j, key);
  if (v == nullptr) return kEmpty;
  if (!v->is_array()) w.fail(std::string(key) + ": not an array");
  return *v;
}

float number(const Json& j, const char* key, float fallback, const Where& w) {
  const Json* v = find_member(j, key);
  if (v == nullptr) return fallback;
  if (!v->is_number()) w.fail(std::string(key) + ": not a number");
  return finite_or_fail(v->get<double>(), w.file, w.element, key);
}

/// An integer member within [lo, hi]; `fallback` when absent.
int integer(const Json& j, const char* key, int fallback, const Where& w, long long lo = INT_MIN,
            long long hi = INT_MAX) {
  const Json* v = find_member(j, key);
  if (v == nullptr) return fallback;
  if (!v->is_number()) w.fail(std::string(key) + ": not an integer");
  return static_cast<int>(whole_or_fail(v->get<double>(), lo, hi, w.file, w.element, key));
}

/// A boolean member; Tiled writes true/false, and 0/1 is taken as well. `fallback` when absent.
bool flag(const Json& j, const char* key, bool fallback, const Where& w) {
  const Json* v = find_member(j, key);
  if (v == nullptr) return fallback;
  if (v->is_boolean()) return v->get<bool>();
  if (v->is_number()) return v->get<double>() != 0.0;
  w.fail(std::string(key) + ": not a boolean");
}

std::string text(const Json& j, const char* key) {
  const Json* v = find_member(j, key);
  return v != nullptr && v->is_string() ? v->get<std::string>() : std::string();
}

/// A tile gid (flip bits included): a whole number in [0, 2^32).
std::uint32_t gid_value(const Json& v, const Where& w, const char* what) {
  if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<long long>() >= 0)) {
    w.fail(std::string(what) + ": not a tile gid");
  }
  const std::uint64_t g = v.get<std::uint64_t>();
  if (g > 0xffffffffu) w.fail(std::string(what) + ": " + std::to_string(g) + " is beyond 32 bits");
  return static_cast<std::uint32_t>(g);
}

std::uint32_t gid(const Json& j, const Where& w) {
  const Json* v = find_member(j, "gid");
  return v == nullptr ? 0 : gid_value(*v, w, "gid");
}

std::vector<Vec2> points(const Json& list, const char* key, const Where& w) {
  if (!list.is_array()) w.fail(std::string(key) + ": not an array");
  if (std::string_view(key) == "polygon" && list.size() > kMaxTiledPolygonPoints) {
    w.fail(std::string(key) + ": " + std::to_string(list.size()) + " points, more than " +
           std::to_string(kMaxTiledPolygonPoints) + " (the limit, kMaxTiledPolygonPoints)");
  }
  std::vector<Vec2> out;
  for (const Json& p : list) {
    if (!p.is_object() || !p.contains("x") || !p.contains("y") || !p["x"].is_number() ||
        !p["y"].is_number()) {
      w.fail(std::string(key) + ": point " + std::to_string(out.size()) + " is not {x, y}");
    }
    out.push_back({finite_or_fail(p["x"].get<double>(), w.file, w.element, key),
                   finite_or_fail(p["y"].get<double>(), w.file, w.element, key)});
  }
  if (out.size() < 2) w.fail(std::string(key) + ": needs at least 2 points");
  return out;
}

/// Reads an object, merging its template. `doc`'s map receives template tilesets (null inside
/// tilesets and templates, where templates are not allowed).
TiledObject read_object(const Json& j, const Where& w, Document* doc) {
  if (!j.is_object()) w.fail("not an object");
  TiledObject obj;
  bool has_shape = false;
  if (j.contains("template")) {
    if (doc == nullptr) w.fail("templates are not allowed here");
    const std::filesystem::path tx = w.file.parent_path() / text(j, "template");
    try {
      const Template& tmpl = external_template(*doc, tx);
      obj = tmpl.object;
      has_shape = has_own_shape(tmpl.object);
      if (tmpl.has_gid) obj.gid = map_template_gid(*doc, tmpl);
    } catch (const InvalidInput& e) {
      w.fail(e.what());  // say which object asked for it
    }
    obj.template_file = tx.generic_string();
  }
  obj.id = integer(j, "id", obj.id, w);
  if (j.contains("name")) obj.name = text(j, "name");
  if (j.contains("type")) obj.type = text(j, "type");
  if (j.contains("class")) obj.type = text(j, "class");
  obj.position = {number(j, "x", obj.position.x, w), number(j, "y", obj.position.y, w)};
  obj.size = {number(j, "width", obj.size.x, w), number(j, "height", obj.size.y, w)};
  if (obj.size.x < 0.0f || obj.size.y < 0.0f) w.fail("width and height must be >= 0");
  obj.rotation = number(j, "rotation", obj.rotation * 180.0f / std::numbers::pi_v<float>, w) *
                 std::numbers::pi_v<float> / 180.0f;
  if (j.contains("gid")) obj.gid = gid(j, w);
  bool own_shape = true;
  if (flag(j, "ellipse", false, w)) {
    obj.kind = TiledShapeKind::ellipse;
  } else if (flag(j, "point", false, w)) {
    obj.kind = TiledShapeKind::point;
  } else if (j.contains("text")) {
    obj.kind = TiledShapeKind::text;
  } else if (const Json* polygon = find_member(j, "polygon")) {
    obj.kind = TiledShapeKind::polygon;
    obj.points = points(*polygon, "polygon", w);
  } else if (const Json* polyline = find_member(j, "polyline")) {
    obj.kind = TiledShapeKind::polyline;
    obj.points = points(*polyline, "polyline", w);
  } else {
    own_shape = false;
  }
  if (!own_shape && !has_shape) obj.kind = obj.gid != 0 ? TiledShapeKind::tile : TiledShapeKind::rectangle;
  return obj;
}

/// One tile of a tileset's "tiles"; `id` from its "id" (Tiled 1.2+) or its key (before 1.2).
void read_tile(const Json& tj, int id, const Where& tw, TiledTileset& ts) {
  if (!tj.is_object()) tw.fail("not an object");
  TiledTile t;
  t.id = id;
  t.image_size = ts.tile_size;
  bool keep = false;
  if (tj.contains("imagewidth") || tj.contains("image")) {
    t.image_size = {number(tj, "imagewidth", ts.tile_size.x, tw), number(tj, "imageheight", ts.tile_size.y, tw)};
    keep = true;
  }
  // Tiled 1.9: a tile of an image collection may use a sub-rectangle of its image.
  if (tj.contains("width") || tj.contains("height")) {
    t.image_size = {number(tj, "width", t.image_size.x, tw), number(tj, "height", t.image_size.y, tw)};
    keep = true;
  }
  if (const Json* group = find_member(tj, "objectgroup")) {
    const Where gw{tw.file, tw.element + ".objectgroup"};
    const Json& objects = array_member(*group, "objects", gw);
    for (size_t k = 0; k < objects.size(); ++k) {
      t.collision.push_back(read_object(objects[k], tw.item("objectgroup.objects", k, objects[k]), nullptr));
    }
    keep = keep || !t.collision.empty();
  }
  if (keep) ts.tiles.push_back(std::move(t));
}

TiledTileset read_tileset(const Json& j, const Where& w) {
  TiledTileset ts;
  ts.name = text(j, "name");
  ts.tile_size = {number(j, "tilewidth", 0.0f, w), number(j, "tileheight", 0.0f, w)};
  ts.tile_count = integer(j, "tilecount", 0, w, 0);
  ts.object_anchor = object_alignment_anchor(text(j, "objectalignment"), w.file, w.element.empty() ? "root" : w.element);
  if (const Json* offset = find_member(j, "tileoffset")) {
    ts.tile_offset = {number(*offset, "x", 0.0f, w), number(*offset, "y", 0.0f, w)};
  }
  const Json* tiles = find_member(j, "tiles");
  if (tiles == nullptr) return ts;
  if (tiles->is_array()) {  // Tiled 1.2+: [{"id": 3, ...}, ...]
    for (size_t i = 0; i < tiles->size(); ++i) {
      const Json& tj = (*tiles)[i];
      const Where tw = w.item("tiles", i, tj);
      if (find_member(tj, "id") == nullptr) tw.fail("id: missing");
      read_tile(tj, integer(tj, "id", 0, tw, 0), tw, ts);
    }
  } else if (tiles->is_object()) {  // before Tiled 1.2: {"3": {...}, ...}, keyed by tile id
    for (const auto& [key, tj] : tiles->items()) {
      const Where tw{w.file, (w.element.empty() ? std::string() : w.element + ".") + "tiles." + key};
      int id = -1;
      const auto [end, ec] = std::from_chars(key.data(), key.data() + key.size(), id);
      if (ec != std::errc() || end != key.data() + key.size() || id < 0) {
        tw.fail("tile id '" + key + "' is not a whole number >= 0");
      }
      read_tile(tj, id, tw, ts);
    }
  } else {
    w.fail("tiles: neither an array (Tiled 1.2+) nor an object keyed by tile id (earlier)");
  }
  sort_tiles(ts);
  return ts;
}

void read_tile_layer(const Json& j, const std::string& name, Vec2 offset, const Where& w,
                     Document& doc) {
  TileLayer layer{name, offset, {}};
  const std::string encoding = j.contains("encoding") ? text(j, "encoding") : "csv";
  const std::string compression = text(j, "compression");
  auto add = [&](const Json& holder, const Where& hw, int x0, int y0, int width, int height) {
    check_tile_block(x0, y0, width, height, hw.file, hw.element.empty() ? "root" : hw.element);
    const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
    std::vector<std::uint32_t> gids;
    const Json* found = find_member(holder, "data");
    if (found == nullptr) hw.fail("data: missing");
    const Json& data = *found;
    if (data.is_array()) {
      if (data.size() != count) {
        hw.fail("data: " + std::to_string(data.size()) + " tiles, expected " + std::to_string(count));
      }
      gids.reserve(count);
      for (const Json& g : data) gids.push_back(gid_value(g, hw, "data"));
    } else if (data.is_string()) {
      gids = decode_tile_data(data.get<std::string>(), encoding, compression, count, hw.file, hw.element);
    } else {
      hw.fail("data: neither an array nor a string");
    }
    add_tile_block(layer, x0, y0, width, gids);
  };
  if (j.contains("chunks")) {
    const Json& chunks = array_member(j, "chunks", w);
    // Every chunk's size is charged before any is decoded.
    for (size_t i = 0; i < chunks.size(); ++i) {
      const Where cw = w.item("chunks", i, chunks[i]);
      if (!chunks[i].is_object()) cw.fail("not an object");
      charge_tiles(doc, static_cast<std::uint64_t>(integer(chunks[i], "width", 0, cw, 0)),
                   static_cast<std::uint64_t>(integer(chunks[i], "height", 0, cw, 0)), cw.file, cw.element);
    }
    for (size_t i = 0; i < chunks.size(); ++i) {
      const Json& c = chunks[i];
      const Where cw = w.item("chunks", i, c);
      if (!c.is_object()) cw.fail("not an object");
      add(c, cw, integer(c, "x", 0, cw), integer(c, "y", 0, cw), integer(c, "width", 0, cw, 0),
          integer(c, "height", 0, cw, 0));
    }
  } else {
    const int width = integer(j, "width", 0, w, 0), height = integer(j, "height", 0, w, 0);
    charge_tiles(doc, static_cast<std::uint64_t>(width), static_cast<std::uint64_t>(height), w.file,
                 w.element.empty() ? "root" : w.element);
    add(j, w, 0, 0, width, height);
  }
  doc.map.tile_cells += static_cast<int>(layer.cells.size());
  doc.tile_layers.push_back(std::move(layer));
}

/// A layer's entry in TiledMap::layers: its class and custom properties (Tiled >= 1.2 writes
/// them as a list of {name, type, value}; older maps as an object of name: value).
TiledLayer layer_entry(const Json& j, std::string name, TiledLayerKind kind, int group) {
  TiledLayer layer;
  layer.name = std::move(name);
  layer.kind = kind;
  layer.type = text(j, "class");
  layer.parent = group;
  const auto as_text = [](const Json& v) { return v.is_string() ? v.get<std::string>() : v.is_null() ? "" : v.dump(); };
  const auto type_of = [](const Json& v) { return v.is_boolean() ? "bool" : v.is_number_integer() ? "int" : v.is_number() ? "float" : "string"; };
  // By reference (find_member): `cond ? j[key] : Json()` would copy the member.
  static const Json kNull;
  const Json* properties = find_member(j, "properties");
  if (properties != nullptr && properties->is_array()) {
    for (const Json& p : *properties) {
      if (!p.is_object()) continue;
      const Json* value = find_member(p, "value");
      const Json& v = value != nullptr ? *value : kNull;
      layer.properties.push_back({text(p, "name"), p.contains("type") ? text(p, "type") : type_of(v), as_text(v)});
    }
  } else if (properties != nullptr && properties->is_object()) {
    for (const auto& [key, value] : properties->items()) layer.properties.push_back({key, type_of(value), as_text(value)});
  }
  return layer;
}

/// The "layers" of `parent` (the map, or a group `depth` levels deep); `group` is the index in
/// TiledMap::layers of the group they are in (-1: the map).
void read_layers(const Json& parent, const std::string& prefix, Vec2 offset, int depth, const Where& w,
                 Document& doc, int group = -1) {
  const Json& list = array_member(parent, "layers", w);
  for (size_t i = 0; i < list.size(); ++i) {
    const Json& j = list[i];
    const Where lw = w.item("layers", i, j);
    if (!j.is_object()) lw.fail("not an object");
    const std::string type = text(j, "type");
    const std::string name = prefix + text(j, "name");
    const Vec2 here = offset + Vec2{number(j, "offsetx", 0.0f, lw), number(j, "offsety", 0.0f, lw)};
    if (type == "group" || type == "tilelayer" || type == "objectgroup" || type == "imagelayer") {
      const TiledLayerKind what = type == "group"       ? TiledLayerKind::group
                                  : type == "tilelayer" ? TiledLayerKind::tile
                                  : type == "imagelayer" ? TiledLayerKind::image : TiledLayerKind::object;
      doc.map.layers.push_back(layer_entry(j, name, what, group));
    }
    if (type == "group") {
      check_group_depth(depth + 1, lw.file, lw.element);
      read_layers(j, name + "/", here, depth + 1, lw, doc, static_cast<int>(doc.map.layers.size()) - 1);
    } else if (type == "tilelayer") {
      read_tile_layer(j, name, here, lw, doc);
    } else if (type == "objectgroup") {
      const Json& objects = array_member(j, "objects", lw);
      for (size_t k = 0; k < objects.size(); ++k) {
        TiledObject obj = read_object(objects[k], lw.item("objects", k, objects[k]), &doc);
        obj.layer = name;
        obj.layer_offset = here;
        doc.map.objects.push_back(std::move(obj));
      }
    }
  }
}

/// Parses `file`; its size goes to `bytes`. Nesting deeper than kMaxJsonDepth is refused before
/// parsing (the parser and the destructor of a parsed value recurse).
Json load_json(const std::filesystem::path& file, std::size_t& bytes) {
  const std::string text = read_input(file);
  bytes = text.size();
  if (const std::size_t at = io::json_too_deep_at(text, kMaxJsonDepth); at != std::string::npos) {
    fail(file, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels (the limit, kMaxJsonDepth) in " +
                   io::json_path_at_syntax_error(std::string_view(text).substr(0, at)),
         "at byte " + std::to_string(at));
  }
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    // e.what() gives the line and the column; parsing again names the element
    fail(file, "JSON syntax error in " + io::json_path_at_syntax_error(text), e.what());
  } catch (const Json::exception& e) {  // out_of_range: a number beyond double range (1e400)
    fail(file, "JSON number out of range in " + io::json_path_at_syntax_error(text), e.what());
  }
}

}  // namespace

TiledTileset read_tileset_json(const std::filesystem::path& file, std::size_t& bytes) {
  const Json root = load_json(file, bytes);
  const Where w{file, ""};
  if (!root.is_object()) w.fail("not a Tiled tileset (not a JSON object)");
  TiledTileset ts = read_tileset(root, w);
  ts.source = file;
  return ts;
}

Template read_template_json(const std::filesystem::path& file, std::size_t& bytes) {
  const Json root = load_json(file, bytes);
  const Where w{file, ""};
  const Json* object = find_member(root, "object");
  if (object == nullptr) w.fail("not a Tiled template (no \"object\")");
  Template t;
  const Where ow{file, "object"};
  t.object = read_object(*object, ow, nullptr);
  t.object.template_file = file.generic_string();
  t.has_gid = object->contains("gid");
  if (const Json* ts = find_member(root, "tileset")) {
    const Where tw{file, "tileset"};
    t.tileset_first_gid = static_cast<std::uint32_t>(integer(*ts, "firstgid", 1, tw, 1, kTiledGidMask));
    if (ts->contains("source")) t.tileset_source = file.parent_path() / text(*ts, "source");
  }
  if (t.has_gid && t.tileset_source.empty()) {
    w.fail("tile object template without an external tileset source");
  }
  return t;
}

/// True for a map before Tiled 1.0, which wrote no "type": an object with "orientation" and
/// "layers" (a scene JSON file has neither, docs/scene-json.md).
bool untyped_tiled_map(const Json& root) {
  return root.is_object() && !root.contains("type") && root.contains("orientation") && root.contains("layers");
}

Document read_tmj(const std::filesystem::path& file) {
  Document doc;
  std::size_t bytes = 0;
  const Json root = load_json(file, bytes);
  charge_bytes(doc, bytes, file);
  const Where w{file, ""};
  if (!(root.is_object() && text(root, "type") == "map") && !untyped_tiled_map(root)) {
    w.fail("not a Tiled map (type is not \"map\")");
  }
  TiledMap& map = doc.map;
  map.path = file;
  map.orientation = text(root, "orientation");
  map.width = integer(root, "width", 0, w, 0);
  map.height = integer(root, "height", 0, w, 0);
  map.tile_size = {number(root, "tilewidth", 0.0f, w), number(root, "tileheight", 0.0f, w)};
  map.infinite = flag(root, "infinite", false, w);
  if (map.orientation != "orthogonal") {
    w.fail("orientation '" + map.orientation + "' is not supported (orthogonal only)");
  }
  const Json& tilesets = array_member(root, "tilesets", w);
  for (size_t i = 0; i < tilesets.size(); ++i) {
    const Json& tj = tilesets[i];
    const Where tw = w.item("tilesets", i, tj);
    if (!tj.is_object()) tw.fail("not an object");
    if (!tj.contains("firstgid")) tw.fail("firstgid: missing");
    const auto first = static_cast<std::uint32_t>(integer(tj, "firstgid", 1, tw, 1, kTiledGidMask));
    TiledTileset ts;
    if (tj.contains("source")) {
      try {
        ts = external_tileset(doc, file.parent_path() / text(tj, "source"));
      } catch (const InvalidInput& e) {
        tw.fail(e.what());  // say which map asked for it
      }
    } else {
      ts = read_tileset(tj, tw);
    }
    ts.first_gid = first;
    map.tilesets.push_back(std::move(ts));
  }
  sort_tilesets(map);
  read_layers(root, "", Vec2{0.0f, 0.0f}, 0, w, doc);
  check_tile_colliders(doc);
  return doc;
}

}  // namespace collide::tiled

namespace collide {

bool looks_like_tiled_json(const std::filesystem::path& path) {
  std::string why;
  const std::optional<std::string> text = io::read_text_file(path, why);
  if (!text || io::json_too_deep_at(*text, kMaxJsonDepth) != std::string::npos) return false;
  const nlohmann::json root = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded() || !root.is_object()) return false;
  const auto type = root.find("type");
  return (type != root.end() && type->is_string()) || tiled::untyped_tiled_map(root);
}

}  // namespace collide
