// The JSON side of Tiled: .tmj/.json maps (nlohmann_json). External tilesets and templates may
// be XML (.tsx/.tx); they go through the XML reader.

#include "json_syntax.hpp"
#include "text_file.hpp"
#include "tiled_document.hpp"

#include <collide/core/error.hpp>

#include <nlohmann/json.hpp>

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
    if (j.is_object() && j.contains("id") && j["id"].is_number()) {
      e.append(" (id=").append(std::to_string(j["id"].get<long long>())).append(")");
    }
    return {file, e};
  }
  [[noreturn]] void fail(std::string_view message) const {
    tiled::fail(file, element.empty() ? "root" : element, message);
  }
};

float number(const Json& j, const char* key, float fallback, const Where& w) {
  if (!j.contains(key)) return fallback;
  const Json& v = j[key];
  if (!v.is_number()) w.fail(std::string(key) + ": not a number");
  return finite_or_fail(v.get<double>(), w.file, w.element, key);
}

int integer(const Json& j, const char* key, int fallback, const Where& w) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_number_integer()) w.fail(std::string(key) + ": not an integer");
  return j[key].get<int>();
}

std::string text(const Json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
}

std::uint32_t gid(const Json& j, const Where& w) {
  if (!j.contains("gid")) return 0;
  if (!j["gid"].is_number_unsigned() && !(j["gid"].is_number_integer() && j["gid"].get<long long>() >= 0)) {
    w.fail("gid: not a tile gid");
  }
  return static_cast<std::uint32_t>(j["gid"].get<std::uint64_t>());
}

std::vector<Vec2> points(const Json& list, const char* key, const Where& w) {
  if (!list.is_array()) w.fail(std::string(key) + ": not an array");
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

TiledObject read_object(const Json& j, const Where& w, TiledMap* map) {
  if (!j.is_object()) w.fail("not an object");
  TiledObject obj;
  bool has_shape = false;
  if (j.contains("template")) {
    if (map == nullptr) w.fail("templates are not allowed here");
    const std::filesystem::path tx = w.file.parent_path() / text(j, "template");
    try {
      const Template tmpl = read_template(tx);
      obj = tmpl.object;
      has_shape = tmpl.has_shape;
      if (tmpl.has_gid) obj.gid = map_template_gid(*map, tmpl);
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
  if (j.value("ellipse", false)) {
    obj.kind = TiledShapeKind::ellipse;
  } else if (j.value("point", false)) {
    obj.kind = TiledShapeKind::point;
  } else if (j.contains("text")) {
    obj.kind = TiledShapeKind::text;
  } else if (j.contains("polygon")) {
    obj.kind = TiledShapeKind::polygon;
    obj.points = points(j["polygon"], "polygon", w);
  } else if (j.contains("polyline")) {
    obj.kind = TiledShapeKind::polyline;
    obj.points = points(j["polyline"], "polyline", w);
  } else {
    own_shape = false;
  }
  if (!own_shape && !has_shape) obj.kind = obj.gid != 0 ? TiledShapeKind::tile : TiledShapeKind::rectangle;
  return obj;
}

TiledTileset read_tileset(const Json& j, const Where& w) {
  TiledTileset ts;
  ts.name = text(j, "name");
  ts.tile_size = {number(j, "tilewidth", 0.0f, w), number(j, "tileheight", 0.0f, w)};
  ts.tile_count = integer(j, "tilecount", 0, w);
  if (j.contains("tileoffset")) {
    ts.tile_offset = {number(j["tileoffset"], "x", 0.0f, w), number(j["tileoffset"], "y", 0.0f, w)};
  }
  if (j.contains("tiles")) {
    if (!j["tiles"].is_array()) w.fail("tiles: not an array");
    for (size_t i = 0; i < j["tiles"].size(); ++i) {
      const Json& tj = j["tiles"][i];
      const Where tw = w.item("tiles", i, tj);
      TiledTile t;
      if (!tj.contains("id")) tw.fail("id: missing");
      t.id = integer(tj, "id", 0, tw);
      t.image_size = ts.tile_size;
      bool keep = false;
      if (tj.contains("imagewidth") || tj.contains("image")) {
        t.image_size = {number(tj, "imagewidth", ts.tile_size.x, tw),
                        number(tj, "imageheight", ts.tile_size.y, tw)};
        keep = true;
      }
      if (tj.contains("objectgroup")) {
        const Json& objects = tj["objectgroup"].value("objects", Json::array());
        for (size_t k = 0; k < objects.size(); ++k) {
          t.collision.push_back(read_object(objects[k], tw.item("objectgroup.objects", k, objects[k]), nullptr));
        }
        keep = keep || !t.collision.empty();
      }
      if (keep) ts.tiles.push_back(std::move(t));
    }
  }
  return ts;
}

void read_tile_layer(const Json& j, const std::string& name, Vec2 offset, const Where& w,
                     Document& doc) {
  TileLayer layer{name, offset, {}};
  const std::string encoding = j.contains("encoding") ? text(j, "encoding") : "csv";
  const std::string compression = text(j, "compression");
  auto add = [&](const Json& holder, const Where& hw, int x0, int y0, int width, int height) {
    if (width < 0 || height < 0) hw.fail("negative width or height");
    const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
    std::vector<std::uint32_t> gids;
    if (!holder.contains("data")) hw.fail("data: missing");
    const Json& data = holder["data"];
    if (data.is_array()) {
      for (const Json& g : data) {
        if (!g.is_number_integer() || g.get<long long>() < 0) hw.fail("data: not a list of tile gids");
        gids.push_back(static_cast<std::uint32_t>(g.get<std::uint64_t>()));
      }
      if (gids.size() != count) {
        hw.fail("data: " + std::to_string(gids.size()) + " tiles, expected " + std::to_string(count));
      }
    } else if (data.is_string()) {
      gids = decode_tile_data(data.get<std::string>(), encoding, compression, count, hw.file, hw.element);
    } else {
      hw.fail("data: neither an array nor a string");
    }
    for (size_t i = 0; i < count; ++i) {
      if (gids[i] != 0) {
        layer.cells.push_back({x0 + static_cast<int>(i) % width, y0 + static_cast<int>(i) / width, gids[i]});
      }
    }
  };
  if (j.contains("chunks")) {
    for (size_t i = 0; i < j["chunks"].size(); ++i) {
      const Json& c = j["chunks"][i];
      const Where cw = w.item("chunks", i, c);
      add(c, cw, integer(c, "x", 0, cw), integer(c, "y", 0, cw), integer(c, "width", 0, cw),
          integer(c, "height", 0, cw));
    }
  } else {
    add(j, w, 0, 0, integer(j, "width", 0, w), integer(j, "height", 0, w));
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
  const Json& properties = j.contains("properties") ? j["properties"] : Json::array();
  if (properties.is_array()) {
    for (const Json& p : properties) {
      if (!p.is_object()) continue;
      const Json& value = p.contains("value") ? p["value"] : Json();
      layer.properties.push_back({text(p, "name"), p.contains("type") ? text(p, "type") : type_of(value), as_text(value)});
    }
  } else if (properties.is_object()) {
    for (const auto& [key, value] : properties.items()) layer.properties.push_back({key, type_of(value), as_text(value)});
  }
  return layer;
}

void read_layers(const Json& list, const std::string& prefix, Vec2 offset, const Where& w,
                 Document& doc, int group = -1) {
  if (!list.is_array()) w.fail("layers: not an array");
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
      read_layers(j.value("layers", Json::array()), name + "/", here, lw, doc,
                  static_cast<int>(doc.map.layers.size()) - 1);
    } else if (type == "tilelayer") {
      read_tile_layer(j, name, here, lw, doc);
    } else if (type == "objectgroup") {
      const Json& objects = j.value("objects", Json::array());
      for (size_t k = 0; k < objects.size(); ++k) {
        TiledObject obj = read_object(objects[k], lw.item("objects", k, objects[k]), &doc.map);
        obj.layer = name;
        obj.layer_offset = here;
        doc.map.objects.push_back(std::move(obj));
      }
    }
  }
}

Json load_json(const std::filesystem::path& file) {
  const std::optional<std::string> read = io::read_text_file(file);
  if (!read) fail(file, "file", "cannot be read");
  const std::string& text = *read;
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

TiledTileset read_tileset_json(const std::filesystem::path& file) {
  const Json root = load_json(file);
  const Where w{file, ""};
  if (!root.is_object()) w.fail("not a Tiled tileset (not a JSON object)");
  TiledTileset ts = read_tileset(root, w);
  ts.source = file;
  return ts;
}

Template read_template_json(const std::filesystem::path& file) {
  const Json root = load_json(file);
  const Where w{file, ""};
  if (!root.is_object() || !root.contains("object")) w.fail("not a Tiled template (no \"object\")");
  Template t;
  const Json& object = root["object"];
  t.object = read_object(object, Where{file, "object"}, nullptr);
  t.has_shape = object.value("ellipse", false) || object.value("point", false) ||
                object.contains("text") || object.contains("polygon") || object.contains("polyline");
  t.has_gid = object.contains("gid");
  if (root.contains("tileset")) {
    const Json& ts = root["tileset"];
    t.tileset_first_gid = static_cast<std::uint32_t>(integer(ts, "firstgid", 1, w));
    if (ts.contains("source")) t.tileset_source = file.parent_path() / text(ts, "source");
  }
  if (t.has_gid && t.tileset_source.empty()) {
    w.fail("tile object template without an external tileset source");
  }
  return t;
}

Document read_tmj(const std::filesystem::path& file) {
  const Json root = load_json(file);
  const Where w{file, ""};
  if (!root.is_object() || text(root, "type") != "map") w.fail("not a Tiled map (type is not \"map\")");
  Document doc;
  TiledMap& map = doc.map;
  map.path = file;
  map.orientation = text(root, "orientation");
  map.width = integer(root, "width", 0, w);
  map.height = integer(root, "height", 0, w);
  map.tile_size = {number(root, "tilewidth", 0.0f, w), number(root, "tileheight", 0.0f, w)};
  map.infinite = root.value("infinite", false);
  if (map.orientation != "orthogonal") {
    w.fail("orientation '" + map.orientation + "' is not supported (orthogonal only)");
  }
  const Json& tilesets = root.value("tilesets", Json::array());
  for (size_t i = 0; i < tilesets.size(); ++i) {
    const Json& tj = tilesets[i];
    const Where tw = w.item("tilesets", i, tj);
    if (!tj.contains("firstgid")) tw.fail("firstgid: missing");
    TiledTileset ts;
    if (tj.contains("source")) {
      try {
        ts = read_tileset_file(file.parent_path() / text(tj, "source"));
      } catch (const InvalidInput& e) {
        tw.fail(e.what());  // say which map asked for it
      }
    } else {
      ts = read_tileset(tj, tw);
    }
    ts.first_gid = static_cast<std::uint32_t>(integer(tj, "firstgid", 1, tw));
    map.tilesets.push_back(std::move(ts));
  }
  read_layers(root.value("layers", Json::array()), "", Vec2{0.0f, 0.0f}, w, doc);
  return doc;
}

}  // namespace collide::tiled

namespace collide {

bool looks_like_tiled_json(const std::filesystem::path& path) {
  const std::optional<std::string> text = io::read_text_file(path);
  if (!text) return false;
  const nlohmann::json root = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded() || !root.is_object()) return false;
  const auto type = root.find("type");
  return type != root.end() && type->is_string();
}

}  // namespace collide
