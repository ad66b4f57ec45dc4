// The XML side of Tiled: .tmx maps, .tsx tilesets, .tx templates (pugixml; no DTD is fetched,
// pugixml never loads external entities).

#include "text_file.hpp"
#include "tiled_document.hpp"

#include <collide/core/error.hpp>

#include <pugixml.hpp>

#include <algorithm>
#include <climits>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <string_view>
#include <vector>

namespace collide::tiled {
namespace {

/// "<object id=12>", "<layer name="Far">", "<tileset firstgid=43>": the element as a reader
/// finds it in the file.
std::string element_label(const pugi::xml_node& node) {
  std::string out = "<";
  out += node.name();
  for (const char* key : {"id", "name", "firstgid"}) {
    if (const pugi::xml_attribute a = node.attribute(key)) {
      out += std::string(" ") + key + "=" + a.value();
      break;
    }
  }
  return out + ">";
}

/// The value of attribute `key` in the raw text of a start tag ("<object id=\"12\" x=..."), or
/// empty. Only for error messages: a tag pugixml could not parse is read leniently.
std::string raw_attribute(std::string_view tag, std::string_view key) {
  for (size_t pos = tag.find(key); pos != std::string_view::npos; pos = tag.find(key, pos + 1)) {
    const bool starts = pos > 0 && (tag[pos - 1] == ' ' || tag[pos - 1] == '\t' || tag[pos - 1] == '\n');
    size_t at = pos + key.size();
    while (at < tag.size() && tag[at] == ' ') ++at;
    if (!starts || at >= tag.size() || tag[at] != '=') continue;
    ++at;
    while (at < tag.size() && tag[at] == ' ') ++at;
    if (at >= tag.size() || (tag[at] != '"' && tag[at] != '\'')) continue;
    const size_t end = tag.find(tag[at], at + 1);
    return std::string(tag.substr(at + 1, end == std::string_view::npos ? std::string_view::npos : end - at - 1));
  }
  return {};
}

/// Where a syntax error at byte `offset` of `text` is, for the message: "line L, column C,
/// inside <map> > <objectgroup name=Walls> > <object id=7>" (the elements open at that point,
/// outermost first, labelled like element_label; "at the top level" outside every element). A plain scan of the tags before
/// the offset: comments, CDATA, processing instructions and the DOCTYPE are skipped.
std::string syntax_error_place(std::string_view text, size_t offset) {
  offset = std::min(offset, text.size());
  size_t line = 1, column = 1;
  for (size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  std::vector<std::string_view> open;  // raw start tags of the elements open at `offset`
  auto skip_to = [&](size_t from, std::string_view end) {
    const size_t at = text.find(end, from);
    return at == std::string_view::npos ? text.size() : at + end.size();
  };
  size_t i = 0;
  while (i < offset) {
    const size_t lt = text.find('<', i);
    if (lt == std::string_view::npos || lt >= offset) break;
    const std::string_view rest = text.substr(lt);
    if (rest.starts_with("<!--")) {
      i = skip_to(lt, "-->");
    } else if (rest.starts_with("<![CDATA[")) {
      i = skip_to(lt, "]]>");
    } else if (rest.starts_with("<?")) {
      i = skip_to(lt, "?>");
    } else if (rest.starts_with("<!")) {
      const size_t bracket = text.find('[', lt), close = text.find('>', lt);
      i = bracket < close ? skip_to(bracket, "]>") : skip_to(lt, ">");
    } else if (rest.starts_with("</")) {
      const size_t close = text.find('>', lt);
      if (close == std::string_view::npos || close >= offset) break;  // the error is in this end tag
      if (!open.empty()) open.pop_back();
      i = close + 1;
    } else {
      size_t end = lt + 1;  // the tag's '>', outside quoted values
      char quote = 0;
      for (; end < text.size(); ++end) {
        if (quote != 0) {
          quote = text[end] == quote ? char(0) : quote;
        } else if (text[end] == '"' || text[end] == '\'') {
          quote = text[end];
        } else if (text[end] == '>') {
          break;
        }
      }
      const bool self_closing = end < text.size() && end > lt + 1 && text[end - 1] == '/' && end < offset;
      if (!self_closing) open.push_back(text.substr(lt, std::min(end, text.size()) - lt));
      i = end + 1;
    }
  }
  std::string place = "line " + std::to_string(line) + ", column " + std::to_string(column);
  if (open.empty()) return place + ", at the top level";
  place += ", inside ";
  for (size_t k = 0; k < open.size(); ++k) {
    const std::string_view tag = open[k];
    size_t name_end = 1;
    while (name_end < tag.size() && std::string_view(" \t\r\n/>").find(tag[name_end]) == std::string_view::npos) {
      ++name_end;
    }
    if (k > 0) place += " > ";
    place += '<';
    place.append(tag.substr(1, name_end - 1));
    for (const char* key : {"id", "name", "firstgid"}) {  // as element_label
      const std::string value = raw_attribute(tag, key);
      if (!value.empty()) {
        place += std::string(" ") + key + "=" + value;
        break;
      }
    }
    place += ">";
  }
  return place;
}

/// Parses `file`; its size goes to `bytes`.
pugi::xml_document load_xml(const std::filesystem::path& file, std::size_t& bytes) {
  const std::string text = read_input(file);
  bytes = text.size();
  pugi::xml_document doc;
  // parse_default skips the DOCTYPE and never resolves external entities.
  const pugi::xml_parse_result result = doc.load_buffer(text.data(), text.size(), pugi::parse_default);
  if (!result) {
    fail(file, "XML syntax error at " + syntax_error_place(text, static_cast<size_t>(std::max<std::ptrdiff_t>(result.offset, 0))),
         result.description());
  }
  return doc;
}

double parse_number(std::string_view text, bool& ok) {
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  ok = ec == std::errc() && ptr == text.data() + text.size();
  return value;
}

/// A numeric attribute; `fallback` when absent. Fails naming the element and attribute when it
/// is not a finite number.
float number(const pugi::xml_node& node, const char* key, float fallback,
             const std::filesystem::path& file) {
  const pugi::xml_attribute a = node.attribute(key);
  if (!a) return fallback;
  bool ok = false;
  const double v = parse_number(a.value(), ok);
  if (!ok) {
    fail(file, element_label(node),
         std::string("attribute ") + key + ": '" + a.value() + "' is not a number");
  }
  return finite_or_fail(v, file, element_label(node), std::string("attribute ") + key);
}

/// An integer attribute within [lo, hi]; `fallback` when absent. Fails naming the element and
/// attribute when it is not a whole number in that range.
int integer(const pugi::xml_node& node, const char* key, int fallback,
            const std::filesystem::path& file, long long lo = INT_MIN, long long hi = INT_MAX) {
  const pugi::xml_attribute a = node.attribute(key);
  if (!a) return fallback;
  bool ok = false;
  const double v = parse_number(a.value(), ok);
  if (!ok) {
    fail(file, element_label(node),
         std::string("attribute ") + key + ": '" + a.value() + "' is not a number");
  }
  return static_cast<int>(whole_or_fail(v, lo, hi, file, element_label(node), std::string("attribute ") + key));
}

std::uint32_t gid_attribute(const pugi::xml_node& node, const std::filesystem::path& file) {
  const pugi::xml_attribute a = node.attribute("gid");
  if (!a) return 0;
  const std::string_view text = a.value();
  std::uint32_t gid = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), gid);
  if (ec != std::errc() || ptr != text.data() + text.size()) {
    fail(file, element_label(node), "attribute gid: '" + std::string(text) + "' is not a tile gid");
  }
  return gid;
}

std::vector<Vec2> parse_points(const pugi::xml_node& shape, const pugi::xml_node& object,
                               const std::filesystem::path& file) {
  std::vector<Vec2> points;
  const std::string_view text = shape.attribute("points").value();
  const std::string what = std::string(shape.name()) + " points";
  const bool polygon = std::string_view(shape.name()) == "polygon";
  size_t pos = 0;
  while (pos < text.size()) {
    if (polygon && points.size() == kMaxTiledPolygonPoints) {
      fail(file, element_label(object), what + ": more than " + std::to_string(kMaxTiledPolygonPoints) +
                                            " points (the limit, kMaxTiledPolygonPoints)");
    }
    while (pos < text.size() && text[pos] == ' ') ++pos;
    if (pos >= text.size()) break;
    size_t end = text.find(' ', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view pair = text.substr(pos, end - pos);
    const size_t comma = pair.find(',');
    bool okx = false, oky = false;
    const double x = comma == std::string_view::npos ? 0.0 : parse_number(pair.substr(0, comma), okx);
    const double y = comma == std::string_view::npos ? 0.0 : parse_number(pair.substr(comma + 1), oky);
    if (!okx || !oky) {
      fail(file, element_label(object), what + ": '" + std::string(pair) + "' is not a pair x,y");
    }
    points.push_back({finite_or_fail(x, file, element_label(object), what),
                      finite_or_fail(y, file, element_label(object), what)});
    pos = end;
  }
  if (points.size() < 2) {
    fail(file, element_label(object), what + ": needs at least 2 points, got " +
                                          std::to_string(points.size()));
  }
  return points;
}

/// Reads the shape child (ellipse, polygon, ...) of an object; false when it has none.
bool read_shape(const pugi::xml_node& node, TiledObject& obj, const std::filesystem::path& file) {
  for (const pugi::xml_node child : node.children()) {
    const std::string_view n = child.name();
    if (n == "ellipse") {
      obj.kind = TiledShapeKind::ellipse;
    } else if (n == "point") {
      obj.kind = TiledShapeKind::point;
    } else if (n == "text") {
      obj.kind = TiledShapeKind::text;
    } else if (n == "polygon" || n == "polyline") {
      obj.kind = n == "polygon" ? TiledShapeKind::polygon : TiledShapeKind::polyline;
      obj.points = parse_points(child, node, file);
    } else {
      continue;
    }
    return true;
  }
  return false;
}

/// Reads an <object>, merging its template. `doc`'s map receives template tilesets (null inside
/// tilesets and templates, where templates are not allowed).
TiledObject read_object(const pugi::xml_node& node, const std::filesystem::path& file,
                        Document* doc) {
  TiledObject obj;
  bool has_shape = false;
  if (const pugi::xml_attribute t = node.attribute("template")) {
    if (doc == nullptr) fail(file, element_label(node), "templates are not allowed here");
    const std::filesystem::path tx = file.parent_path() / t.value();
    try {
      const Template& tmpl = external_template(*doc, tx);
      obj = tmpl.object;
      has_shape = has_own_shape(tmpl.object);
      if (tmpl.has_gid) obj.gid = map_template_gid(*doc, tmpl);
    } catch (const InvalidInput& e) {
      fail(file, element_label(node), e.what());  // say which object asked for it
    }
    obj.template_file = tx.generic_string();
  }
  obj.id = integer(node, "id", obj.id, file);
  if (const pugi::xml_attribute a = node.attribute("name")) obj.name = a.value();
  if (const pugi::xml_attribute a = node.attribute("type")) obj.type = a.value();
  if (const pugi::xml_attribute a = node.attribute("class")) obj.type = a.value();
  obj.position = {number(node, "x", obj.position.x, file), number(node, "y", obj.position.y, file)};
  obj.size = {number(node, "width", obj.size.x, file), number(node, "height", obj.size.y, file)};
  if (obj.size.x < 0.0f || obj.size.y < 0.0f) {
    fail(file, element_label(node), "width and height must be >= 0");
  }
  const float degrees = number(node, "rotation", obj.rotation * 180.0f / std::numbers::pi_v<float>, file);
  obj.rotation = degrees * std::numbers::pi_v<float> / 180.0f;
  if (node.attribute("gid")) obj.gid = gid_attribute(node, file);
  // Without a shape element of its own or its template's, an object is a tile or a rectangle.
  if (!read_shape(node, obj, file) && !has_shape) {
    obj.kind = obj.gid != 0 ? TiledShapeKind::tile : TiledShapeKind::rectangle;
  }
  return obj;
}

TiledTileset read_tileset_node(const pugi::xml_node& node, const std::filesystem::path& file) {
  TiledTileset ts;
  ts.name = node.attribute("name").value();
  ts.tile_size = {number(node, "tilewidth", 0.0f, file), number(node, "tileheight", 0.0f, file)};
  ts.tile_count = integer(node, "tilecount", 0, file, 0);
  ts.object_anchor = object_alignment_anchor(node.attribute("objectalignment").value(), file, element_label(node));
  if (const pugi::xml_node off = node.child("tileoffset")) {
    ts.tile_offset = {number(off, "x", 0.0f, file), number(off, "y", 0.0f, file)};
  }
  for (const pugi::xml_node tile : node.children("tile")) {
    TiledTile t;
    if (!tile.attribute("id")) fail(file, element_label(tile), "attribute id: missing");
    t.id = integer(tile, "id", 0, file, 0);
    t.image_size = ts.tile_size;
    bool keep = false;
    if (const pugi::xml_node image = tile.child("image")) {
      t.image_size = {number(image, "width", ts.tile_size.x, file),
                      number(image, "height", ts.tile_size.y, file)};
      keep = true;
    }
    // Tiled 1.9: a tile of an image collection may use a sub-rectangle of its image.
    if (tile.attribute("width") || tile.attribute("height")) {
      t.image_size = {number(tile, "width", t.image_size.x, file), number(tile, "height", t.image_size.y, file)};
      keep = true;
    }
    if (const pugi::xml_node group = tile.child("objectgroup")) {
      for (const pugi::xml_node o : group.children("object")) {
        t.collision.push_back(read_object(o, file, nullptr));
      }
      keep = keep || !t.collision.empty();
    }
    if (keep) ts.tiles.push_back(std::move(t));
  }
  sort_tiles(ts);
  return ts;
}

void read_tile_layer(const pugi::xml_node& node, const std::string& name, Vec2 offset,
                     const std::filesystem::path& file, Document& doc) {
  TileLayer layer{name, offset, {}};
  const pugi::xml_node data = node.child("data");
  if (!data) fail(file, element_label(node), "has no <data>");
  const std::string encoding = data.attribute("encoding").value();
  const std::string compression = data.attribute("compression").value();
  auto add = [&](const pugi::xml_node& holder, int x0, int y0, int w, int h) {
    const std::string where = holder == data ? element_label(node) : element_label(node) + ": " + element_label(holder);
    check_tile_block(x0, y0, w, h, file, where);
    const size_t count = static_cast<size_t>(w) * static_cast<size_t>(h);
    std::vector<std::uint32_t> gids;
    if (encoding.empty()) {  // legacy: one <tile gid=".."/> per cell
      for (const pugi::xml_node t : holder.children("tile")) {
        if (gids.size() == count) {
          fail(file, where, "more <tile> elements than width x height (" + std::to_string(count) + ")");
        }
        gids.push_back(gid_attribute(t, file));
      }
      if (gids.size() != count) {
        fail(file, where, "<tile> count " + std::to_string(gids.size()) + " is not width x height (" +
                              std::to_string(count) + ")");
      }
    } else {
      gids = decode_tile_data(holder.text().get(), encoding, compression, count, file, where);
    }
    add_tile_block(layer, x0, y0, w, gids);
  };
  if (data.child("chunk")) {
    // Every chunk's size is charged before any is decoded.
    for (const pugi::xml_node chunk : data.children("chunk")) {
      charge_tiles(doc, static_cast<std::uint64_t>(integer(chunk, "width", 0, file, 0)),
                   static_cast<std::uint64_t>(integer(chunk, "height", 0, file, 0)), file,
                   element_label(node) + ": " + element_label(chunk));
    }
    for (const pugi::xml_node chunk : data.children("chunk")) {
      add(chunk, integer(chunk, "x", 0, file), integer(chunk, "y", 0, file),
          integer(chunk, "width", 0, file, 0), integer(chunk, "height", 0, file, 0));
    }
  } else {
    const int w = integer(node, "width", 0, file, 0), h = integer(node, "height", 0, file, 0);
    charge_tiles(doc, static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h), file, element_label(node));
    add(data, 0, 0, w, h);
  }
  doc.map.tile_cells += static_cast<int>(layer.cells.size());
  doc.tile_layers.push_back(std::move(layer));
}

/// A layer's entry in TiledMap::layers: its class and custom properties.
TiledLayer layer_entry(const pugi::xml_node& node, std::string name, TiledLayerKind kind, int group) {
  TiledLayer layer;
  layer.name = std::move(name);
  layer.kind = kind;
  layer.type = node.attribute("class").value();
  layer.parent = group;
  for (const pugi::xml_node p : node.child("properties").children("property")) {
    const pugi::xml_attribute value = p.attribute("value");  // multi-line strings are the text
    layer.properties.push_back({p.attribute("name").value(), p.attribute("type") ? p.attribute("type").value() : "string",
                                value ? value.value() : p.text().get()});
  }
  return layer;
}

/// The layers under `parent`, a group `depth` levels deep (0: the map); `group` is the index in
/// TiledMap::layers of that group (-1: the map).
void read_layers(const pugi::xml_node& parent, const std::string& prefix, Vec2 offset, int depth,
                 const std::filesystem::path& file, Document& doc, int group = -1) {
  for (const pugi::xml_node node : parent.children()) {
    const std::string_view kind = node.name();
    if (kind == "imagelayer") {
      doc.map.layers.push_back(layer_entry(node, prefix + node.attribute("name").value(), TiledLayerKind::image, group));
    }
    if (kind != "layer" && kind != "objectgroup" && kind != "group") continue;
    const std::string name = prefix + node.attribute("name").value();
    const Vec2 here = offset + Vec2{number(node, "offsetx", 0.0f, file),
                                    number(node, "offsety", 0.0f, file)};
    const TiledLayerKind what = kind == "group" ? TiledLayerKind::group
                                : kind == "layer" ? TiledLayerKind::tile : TiledLayerKind::object;
    doc.map.layers.push_back(layer_entry(node, name, what, group));
    if (kind == "group") {
      check_group_depth(depth + 1, file, element_label(node));
      read_layers(node, name + "/", here, depth + 1, file, doc, static_cast<int>(doc.map.layers.size()) - 1);
    } else if (kind == "layer") {
      read_tile_layer(node, name, here, file, doc);
    } else {
      for (const pugi::xml_node o : node.children("object")) {
        TiledObject obj = read_object(o, file, &doc);
        obj.layer = name;
        obj.layer_offset = here;
        doc.map.objects.push_back(std::move(obj));
      }
    }
  }
}

}  // namespace

TiledTileset read_tileset_file(const std::filesystem::path& file, std::size_t& bytes) {
  const std::string ext = file.extension().string();
  if (ext == ".tsj" || ext == ".json") return read_tileset_json(file, bytes);
  const pugi::xml_document doc = load_xml(file, bytes);
  const pugi::xml_node root = doc.child("tileset");
  if (!root) fail(file, "root", "not a Tiled tileset (no <tileset> element)");
  TiledTileset ts = read_tileset_node(root, file);
  ts.source = file;
  return ts;
}

Template read_template(const std::filesystem::path& file, std::size_t& bytes) {
  // Read once per load (external_template); a cache across loads would go stale while a game
  // reloads edited maps.
  if (file.extension() == ".tj") return read_template_json(file, bytes);
  const pugi::xml_document doc = load_xml(file, bytes);
  const pugi::xml_node root = doc.child("template");
  if (!root) fail(file, "root", "not a Tiled template (no <template> element)");
  const pugi::xml_node object = root.child("object");
  if (!object) fail(file, "<template>", "has no <object>");
  Template t;
  t.object = read_object(object, file, nullptr);
  t.object.template_file = file.generic_string();
  t.has_gid = object.attribute("gid");
  if (const pugi::xml_node ts = root.child("tileset")) {
    t.tileset_first_gid = static_cast<std::uint32_t>(integer(ts, "firstgid", 1, file, 1, kTiledGidMask));
    if (ts.attribute("source")) t.tileset_source = file.parent_path() / ts.attribute("source").value();
  }
  if (t.has_gid && t.tileset_source.empty()) {
    fail(file, "<template>", "tile object template without an external <tileset source>");
  }
  return t;
}

Document read_tmx(const std::filesystem::path& file) {
  Document doc;
  std::size_t bytes = 0;
  const pugi::xml_document xml = load_xml(file, bytes);
  charge_bytes(doc, bytes, file);
  const pugi::xml_node root = xml.child("map");
  if (!root) fail(file, "root", "not a Tiled map (no <map> element)");
  TiledMap& map = doc.map;
  map.path = file;
  map.orientation = root.attribute("orientation").value();
  map.width = integer(root, "width", 0, file, 0);
  map.height = integer(root, "height", 0, file, 0);
  map.tile_size = {number(root, "tilewidth", 0.0f, file), number(root, "tileheight", 0.0f, file)};
  map.infinite = integer(root, "infinite", 0, file) != 0;
  if (map.orientation != "orthogonal") {
    fail(file, "<map>", "orientation '" + map.orientation + "' is not supported (orthogonal only)");
  }
  for (const pugi::xml_node node : root.children("tileset")) {
    if (!node.attribute("firstgid")) fail(file, element_label(node), "attribute firstgid: missing");
    const auto first = static_cast<std::uint32_t>(integer(node, "firstgid", 1, file, 1, kTiledGidMask));
    TiledTileset ts;
    if (node.attribute("source")) {
      try {
        ts = external_tileset(doc, file.parent_path() / node.attribute("source").value());
      } catch (const InvalidInput& e) {
        fail(file, element_label(node), e.what());  // say which map asked for it
      }
    } else {
      ts = read_tileset_node(node, file);
    }
    ts.first_gid = first;
    map.tilesets.push_back(std::move(ts));
  }
  sort_tilesets(map);
  read_layers(root, "", Vec2{0.0f, 0.0f}, 0, file, doc);
  check_tile_colliders(doc);
  return doc;
}

}  // namespace collide::tiled
