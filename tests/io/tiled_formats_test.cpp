// Tiled's file formats across versions (docs/tiled-formats.md: one test per change that affects
// what collide reads) and hostile Tiled input refused at the limits of docs/limits.md.

#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>
#include <collide/io/scene_json.hpp>
#include <collide/io/tiled.hpp>

#include "support/test_util.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace collide {
namespace {

namespace fs = std::filesystem;

/// A scratch folder for synthetic maps, removed with the test.
class Scratch {
 public:
  Scratch() {
    path_ = fs::temp_directory_path() /
            ("collide_tiledfmt_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~Scratch() { fs::remove_all(path_); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name, std::ios::binary) << text;
    return path_ / name;
  }
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string error_of(const fs::path& file) {
  try {
    (void)load_tiled_map(file);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no error";
}

#define EXPECT_ERROR_HAS(message, part) \
  EXPECT_NE((message).find(part), std::string::npos) << "'" << (part) << "' not in: " << (message)

/// Tile 0 of this tileset has a 4 x 2 box at its top-left corner; tile 1 has none.
const char* kTsx = R"(<tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="4">
  <tile id="0"><objectgroup><object id="1" x="0" y="0" width="4" height="2"/></objectgroup></tile></tileset>)";

std::string tmx(const std::string& body, const std::string& tileset = kTsx, const std::string& extra = "") {
  return std::string(R"(<map version="1.10" orientation="orthogonal" width="4" height="3" tilewidth="16" tileheight="16" )") +
         extra + ">\n" + tileset + "\n" + body + "\n</map>\n";
}

/// World AABB of every collider.
Aabb bounds(const TiledMap& map) {
  Aabb box = compute_aabb(map.colliders.at(0).shape, map.colliders.at(0).transform);
  for (const TiledCollider& c : map.colliders) box = merge(box, compute_aabb(c.shape, c.transform));
  return box;
}

// ---- every version Tiled has written -----------------------------------------------------------

// Tiled 1.0 (JSON format before 1.2, as melonJS's examples): an external tileset whose "tiles"
// is an object keyed by tile id, "tileproperties" and "propertytypes", properties as a plain
// object, "version" a number. Before: "tiles: not an array".
TEST(TiledFormats, Tiled10JsonTilesetKeyedByTileIdReads) {
  Scratch dir;
  dir.write("old.json", R"({"type": "tileset", "name": "old", "tilewidth": 16, "tileheight": 16, "tilecount": 4,
    "columns": 2, "image": "old.png", "imagewidth": 32, "imageheight": 32, "margin": 0, "spacing": 0,
    "properties": {"solid": "true"}, "propertytypes": {"solid": "bool"},
    "tileproperties": {"2": {"kind": "wall"}}, "tilepropertytypes": {"2": {"kind": "string"}},
    "tiles": {"2": {"objectgroup": {"draworder": "index", "name": "", "objects": [
        {"id": 1, "x": 0, "y": 8, "width": 16, "height": 8, "rotation": 0, "type": "", "visible": true}],
        "opacity": 1, "type": "objectgroup", "visible": true, "x": 0, "y": 0}},
              "0": {"terrain": [0, 0, 0, 0]}},
    "tiledversion": "1.0.3", "version": 1})");
  const fs::path map = dir.write("map.json", R"({"type": "map", "version": 1, "tiledversion": "1.0.3",
    "orientation": "orthogonal", "renderorder": "right-down", "width": 2, "height": 1, "tilewidth": 16, "tileheight": 16,
    "nextobjectid": 1, "properties": {"gravity": "9.8"}, "propertytypes": {"gravity": "float"},
    "tilesets": [{"firstgid": 1, "source": "old.json"}],
    "layers": [{"type": "tilelayer", "name": "walls", "width": 2, "height": 1, "x": 0, "y": 0, "opacity": 1,
                "visible": true, "properties": {"collides": "true"}, "data": [3, 1]}]})");
  const TiledMap m = load_tiled_map(map);
  ASSERT_EQ(m.colliders.size(), 1u);  // tile 2 (gid 3) has a box; tile 0 (gid 1) has none
  EXPECT_EQ(m.colliders[0].source.cell_x, 0);
  EXPECT_VEC2_NEAR(bounds(m).min, Vec2(0, 8), 1e-5f);
  EXPECT_VEC2_NEAR(bounds(m).max, Vec2(16, 16), 1e-5f);
  // An embedded tileset of that era too, and a key that is no tile id is named.
  const fs::path embedded = dir.write("embedded.json", R"({"type": "map", "orientation": "orthogonal", "width": 1, "height": 1,
    "tilewidth": 16, "tileheight": 16, "tilesets": [{"firstgid": 5, "name": "e", "tilewidth": 16, "tileheight": 16,
      "tiles": {"0": {"objectgroup": {"objects": [{"id": 1, "x": 0, "y": 0, "width": 2, "height": 2}]}}}}],
    "layers": [{"type": "tilelayer", "name": "l", "width": 1, "height": 1, "data": [5]}]})");
  EXPECT_EQ(load_tiled_map(embedded).colliders.size(), 1u);
  const std::string bad = error_of(dir.write("badkey.json", R"({"type": "map", "orientation": "orthogonal", "width": 1,
    "height": 1, "tilewidth": 16, "tileheight": 16, "tilesets": [{"firstgid": 1, "tiles": {"x7": {}}}], "layers": []})"));
  EXPECT_ERROR_HAS(bad, "tilesets[0].tiles.x7");
  EXPECT_ERROR_HAS(bad, "not a whole number");
}

// Before Tiled 1.0 a JSON map had no "type". Before: "not a Tiled map".
TEST(TiledFormats, Pre10JsonMapWithoutTypeReads) {
  Scratch dir;
  const fs::path map = dir.write("pre10.json", R"({"version": 1, "orientation": "orthogonal", "width": 1, "height": 1,
    "tilewidth": 8, "tileheight": 8, "properties": {}, "tilesets": [],
    "layers": [{"type": "objectgroup", "name": "o", "objects": [{"id": 1, "x": 1, "y": 2, "width": 3, "height": 4}]}]})");
  EXPECT_TRUE(looks_like_tiled_json(map));
  const TiledMap m = load_tiled_map(map);
  ASSERT_EQ(m.colliders.size(), 1u);
  EXPECT_VEC2_NEAR(bounds(m).max, Vec2(4, 6), 1e-5f);
  // A scene file (no "orientation", no "layers") is still not taken for a map.
  EXPECT_FALSE(looks_like_tiled_json(dir.write("scene.json", R"({"bodies": [], "statics": []})")));
}

// Tiled 1.6 writes "version" as a string ("1.6"), before as a number (1.5); neither matters.
TEST(TiledFormats, VersionAsNumberOrStringReads) {
  Scratch dir;
  for (const char* version : {"1.5", "\"1.6\"", "\"1.11\""}) {
    const fs::path map = dir.write("v.tmj", std::string(R"({"type": "map", "version": )") + version +
                                                R"(, "orientation": "orthogonal", "width": 1, "height": 1,
      "tilewidth": 8, "tileheight": 8, "layers": [{"type": "objectgroup", "name": "o",
        "objects": [{"id": 1, "x": 0, "y": 0, "width": 3, "height": 4}]}]})");
    EXPECT_EQ(load_tiled_map(map).colliders.size(), 1u) << version;
  }
}

// Tiled 1.9 wrote an object's type as "class"; 1.10 went back to "type" (both formats).
TEST(TiledFormats, ObjectClassOfTiled19AndTypeOfOthersAreBothRead) {
  Scratch dir;
  const TiledMap x = load_tiled_map(dir.write("c.tmx", tmx(R"(<objectgroup name="o">
      <object id="1" class="Wall" x="0" y="0" width="2" height="2"/>
      <object id="2" type="Door" x="4" y="0" width="2" height="2"/></objectgroup>)")));
  const TiledMap j = load_tiled_map(dir.write("c.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 1,
    "height": 1, "tilewidth": 8, "tileheight": 8, "layers": [{"type": "objectgroup", "name": "o", "objects": [
      {"id": 1, "class": "Wall", "x": 0, "y": 0, "width": 2, "height": 2},
      {"id": 2, "type": "Door", "x": 4, "y": 0, "width": 2, "height": 2}]}]})"));
  for (const TiledMap* m : {&x, &j}) {
    ASSERT_EQ(m->objects.size(), 2u);
    EXPECT_EQ(m->objects[0].type, "Wall");
    EXPECT_EQ(m->objects[1].type, "Door");
    EXPECT_EQ(m->colliders[0].source.type, "Wall");
  }
}

// Tiled 1.9: a tile of an image collection may use a sub-rectangle (x, y, width, height) of its
// image; a tile object without collision shapes then covers that rectangle's size, not the image's.
TEST(TiledFormats, Tiled19TileSubRectangleSizesTheTileObject) {
  Scratch dir;
  const std::string tileset = R"(<tileset firstgid="1" name="c" tilewidth="64" tileheight="64" tilecount="1" columns="0">
    <tile id="0" x="8" y="8" width="20" height="10"><image width="64" height="64" source="sheet.png"/></tile></tileset>)";
  const TiledMap x = load_tiled_map(dir.write("s.tmx", tmx(R"(<objectgroup name="o"><object id="1" gid="1" x="100" y="50"/></objectgroup>)", tileset)));
  const TiledMap j = load_tiled_map(dir.write("s.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 1,
    "height": 1, "tilewidth": 8, "tileheight": 8, "tilesets": [{"firstgid": 1, "name": "c", "tilewidth": 64,
      "tileheight": 64, "tilecount": 1, "tiles": [{"id": 0, "image": "sheet.png", "imagewidth": 64, "imageheight": 64,
      "x": 8, "y": 8, "width": 20, "height": 10}]}],
    "layers": [{"type": "objectgroup", "name": "o", "objects": [{"id": 1, "gid": 1, "x": 100, "y": 50}]}]})"));
  for (const TiledMap* m : {&x, &j}) {
    ASSERT_EQ(m->colliders.size(), 1u);
    EXPECT_VEC2_NEAR(bounds(*m).min, Vec2(100, 40), 1e-4f);
    EXPECT_VEC2_NEAR(bounds(*m).max, Vec2(120, 50), 1e-4f);
  }
}

// Tiled 1.4 added a tileset's objectalignment: which point of a tile object's rectangle sits on
// its position (and is the centre of its rotation). Before: always bottom-left, so a map that set
// "topleft" had every tile object one object height too high.
TEST(TiledFormats, Tiled14ObjectAlignmentAnchorsTileObjects) {
  Scratch dir;
  struct Case {
    const char* alignment;  // "" leaves the attribute out
    float rotation;         // degrees, clockwise
    Vec2 min, max;          // the 4 x 2 collision box of tile 0, world
  };
  // Tile object gid 1, 16 x 16, at (100, 50); tile 0's box is its top-left 4 x 2 pixels.
  const Case cases[] = {
      {"", 0.0f, {100, 34}, {104, 36}},           {"unspecified", 0.0f, {100, 34}, {104, 36}},
      {"bottomleft", 0.0f, {100, 34}, {104, 36}}, {"topleft", 0.0f, {100, 50}, {104, 52}},
      {"center", 0.0f, {92, 42}, {96, 44}},       {"bottomright", 0.0f, {84, 34}, {88, 36}},
      {"top", 0.0f, {92, 50}, {96, 52}},          {"right", 0.0f, {84, 42}, {88, 44}},
      // Rotated half a turn about the centre: the box goes to the bottom-right of the tile.
      {"center", 180.0f, {104, 56}, {108, 58}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string("objectalignment '") + c.alignment + "', rotation " + std::to_string(c.rotation));
    const std::string attribute = *c.alignment != 0 ? std::string(" objectalignment=\"") + c.alignment + "\"" : "";
    const std::string member = *c.alignment != 0 ? std::string(", \"objectalignment\": \"") + c.alignment + "\"" : "";
    const std::string rotation = std::to_string(c.rotation);
    const TiledMap x = load_tiled_map(dir.write("a.tmx", tmx(R"(<objectgroup name="o"><object id="1" gid="1" x="100" y="50" width="16" height="16" rotation=")" +
                                                             rotation + R"("/></objectgroup>)",
                                                         R"(<tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="4")" +
                                                             attribute + R"(>
  <tile id="0"><objectgroup><object id="1" x="0" y="0" width="4" height="2"/></objectgroup></tile></tileset>)")));
    const TiledMap j = load_tiled_map(dir.write("a.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 4,
      "height": 3, "tilewidth": 16, "tileheight": 16, "tilesets": [{"firstgid": 1, "name": "t", "tilewidth": 16,
        "tileheight": 16, "tilecount": 4)" + member + R"(, "tiles": [{"id": 0, "objectgroup": {"objects": [
          {"id": 1, "x": 0, "y": 0, "width": 4, "height": 2}]}}]}],
      "layers": [{"type": "objectgroup", "name": "o", "objects": [{"id": 1, "gid": 1, "x": 100, "y": 50,
        "width": 16, "height": 16, "rotation": )" + rotation + "}]}]}"));
    for (const TiledMap* m : {&x, &j}) {
      ASSERT_EQ(m->colliders.size(), 1u);
      EXPECT_VEC2_NEAR(bounds(*m).min, c.min, 1e-3f);
      EXPECT_VEC2_NEAR(bounds(*m).max, c.max, 1e-3f);
    }
  }
  // A tile without collision shapes becomes its image rectangle, anchored the same way.
  const TiledMap boxed = load_tiled_map(dir.write("b.tmx", tmx(R"(<objectgroup name="o"><object id="1" gid="2" x="100" y="50" width="16" height="16"/></objectgroup>)",
                                                           R"(<tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="4" objectalignment="topleft"/>)")));
  ASSERT_EQ(boxed.colliders.size(), 1u);
  EXPECT_VEC2_NEAR(bounds(boxed).min, Vec2(100, 50), 1e-3f);
  EXPECT_VEC2_NEAR(bounds(boxed).max, Vec2(116, 66), 1e-3f);
  // A word Tiled never writes is named, with the element.
  const std::string error = error_of(dir.write("c.tmx", tmx("", R"(<tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="4" objectalignment="middle"/>)")));
  EXPECT_ERROR_HAS(error, "c.tmx: <tileset");
  EXPECT_ERROR_HAS(error, "objectalignment 'middle': not one of");
}

// Tiled 1.3 added zstd-compressed tile data. Before: refused.
TEST(TiledFormats, ZstdTileDataReadsAsTheOtherEncodings) {
  Scratch dir;
  // gids 1 0 2 0 / 0 2 0 0 / 0 0 0 1 (zstd -c of the 48 little-endian bytes, base64).
  const TiledMap z = load_tiled_map(dir.write("z.tmx", tmx(
      R"(<layer name="L" width="4" height="3"><data encoding="base64" compression="zstd">KLUv/QRYpQAAQAEAAgABAAAABACAgxcOwMYDwAJ/R2tL</data></layer>)")));
  const TiledMap c = load_tiled_map(dir.write("c.tmx", tmx(
      R"(<layer name="L" width="4" height="3"><data encoding="csv">1,0,2,0,0,2,0,0,0,0,0,1</data></layer>)")));
  EXPECT_EQ(z.tile_cells, 4);
  ASSERT_EQ(z.colliders.size(), c.colliders.size());
  EXPECT_EQ(z.colliders.size(), 2u);  // gid 1 twice; tile 1 (gid 2) has no shapes
  EXPECT_VEC2_NEAR(bounds(z).min, bounds(c).min, 0.0f);
  EXPECT_VEC2_NEAR(bounds(z).max, bounds(c).max, 0.0f);
  // The same data in a JSON chunk of an infinite map; a corrupt or too long stream is named.
  const TiledMap j = load_tiled_map(dir.write("z.tmj", R"({"type": "map", "orientation": "orthogonal", "infinite": true,
    "width": 4, "height": 3, "tilewidth": 16, "tileheight": 16,
    "tilesets": [{"firstgid": 1, "name": "t", "tilewidth": 16, "tileheight": 16, "tilecount": 4, "tiles": [
      {"id": 0, "objectgroup": {"objects": [{"id": 1, "x": 0, "y": 0, "width": 4, "height": 2}]}}]}],
    "layers": [{"type": "tilelayer", "name": "L", "encoding": "base64", "compression": "zstd", "chunks": [
      {"x": -4, "y": 0, "width": 4, "height": 3, "data": "KLUv/QRYpQAAQAEAAgABAAAABACAgxcOwMYDwAJ/R2tL"}]}]})"));
  EXPECT_EQ(j.colliders.size(), 2u);
  EXPECT_ERROR_HAS(error_of(dir.write("short.tmx", tmx(R"(<layer name="L" width="4" height="2"><data encoding="base64" compression="zstd">KLUv/QRYpQAAQAEAAgABAAAABACAgxcOwMYDwAJ/R2tL</data></layer>)"))),
                   "more data than width x height");
}

// Old TMX: no object ids (before 0.11), no tilecount (before 0.13), a tileset <image> child,
// <data> as <tile gid> elements, gzip (deprecated in 0.15); all still read.
TEST(TiledFormats, OldTmxWithoutIdsTilecountOrEncodingReads) {
  Scratch dir;
  const std::string tileset = R"(<tileset firstgid="1" name="t" tilewidth="16" tileheight="16">
    <image source="tiles.png" width="64" height="16"/>
    <tile id="0"><objectgroup><object x="0" y="0" width="4" height="2"/></objectgroup></tile></tileset>)";
  const TiledMap m = load_tiled_map(dir.write("old.tmx", "<?xml version=\"1.0\"?>\n<!DOCTYPE map SYSTEM \"http://mapeditor.org/dtd/1.0/map.dtd\">\n" + tmx(
      R"(<layer name="L" width="2" height="1"><data><tile gid="1"/><tile gid="0"/></data></layer>
         <objectgroup name="o"><object x="40" y="0" width="8" height="8"/></objectgroup>)", tileset)));
  EXPECT_EQ(m.colliders.size(), 2u);
}

// ---- hostile input -----------------------------------------------------------------------------

// 100,000 nested group layers overflowed the stack (both formats). Now refused at
// kMaxTiledGroupDepth, or for JSON first at kMaxJsonDepth, before any recursion.
TEST(TiledHostile, DeepGroupNestingIsRefusedAtTheLimit) {
  Scratch dir;
  auto xml_groups = [](int n) {
    std::string s;
    for (int i = 0; i < n; ++i) s += "<group name=\"g\">";
    s += R"(<objectgroup name="o"><object id="1" x="0" y="0" width="2" height="2"/></objectgroup>)";
    for (int i = 0; i < n; ++i) s += "</group>";
    return s;
  };
  auto json_groups = [](int n) {
    std::string s = R"({"type": "map", "orientation": "orthogonal", "width": 1, "height": 1, "tilewidth": 8, "tileheight": 8, "layers": [)";
    for (int i = 0; i < n; ++i) s += R"({"type": "group", "name": "g", "layers": [)";
    s += R"({"type": "objectgroup", "name": "o", "objects": [{"id": 1, "x": 0, "y": 0, "width": 2, "height": 2}]})";
    for (int i = 0; i < n; ++i) s += "]}";
    return s + "]}";
  };
  EXPECT_EQ(load_tiled_map(dir.write("ok.tmx", tmx(xml_groups(kMaxTiledGroupDepth)))).colliders.size(), 1u);
  EXPECT_EQ(load_tiled_map(dir.write("ok.tmj", json_groups(kMaxTiledGroupDepth))).colliders.size(), 1u);
  for (const int n : {kMaxTiledGroupDepth + 1, 100000}) {
    const std::string x = error_of(dir.write("deep.tmx", tmx(xml_groups(n))));
    EXPECT_ERROR_HAS(x, "deep.tmx: <group name=g>");
    EXPECT_ERROR_HAS(x, "kMaxTiledGroupDepth");
  }
  EXPECT_ERROR_HAS(error_of(dir.write("deep.tmj", json_groups(kMaxTiledGroupDepth + 1))), "kMaxTiledGroupDepth");
  const std::string j = error_of(dir.write("deeper.tmj", json_groups(100000)));
  EXPECT_ERROR_HAS(j, "deeper.tmj: JSON nested deeper than 256 levels");
  EXPECT_ERROR_HAS(j, "kMaxJsonDepth");
}

// A 300-byte map declaring a 46341 x 46341 layer reserved gigabytes; chunks add up too.
TEST(TiledHostile, DeclaredTileCountIsCheckedBeforeDecoding) {
  Scratch dir;
  const std::string x = error_of(dir.write("huge.tmx", tmx(R"(<layer name="L" width="46341" height="46341"><data encoding="csv">1</data></layer>)")));
  EXPECT_ERROR_HAS(x, "huge.tmx: <layer name=L>");
  EXPECT_ERROR_HAS(x, "46341 x 46341");
  EXPECT_ERROR_HAS(x, "kMaxTiledMapTiles");
  const std::string j = error_of(dir.write("huge.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 1,
    "height": 1, "tilewidth": 8, "tileheight": 8, "layers": [{"type": "tilelayer", "name": "L", "width": 46341,
    "height": 46341, "encoding": "base64", "compression": "zlib", "data": "eJxjYAAAAAQAAQ=="}]})"));
  EXPECT_ERROR_HAS(j, "layers[0]");
  EXPECT_ERROR_HAS(j, "kMaxTiledMapTiles");
  // Many chunks, each within the limit, together past it.
  std::string chunks;
  for (int i = 0; i < 5; ++i) {
    chunks += "<chunk x=\"" + std::to_string(i * 4096) + "\" y=\"0\" width=\"4096\" height=\"1024\">0</chunk>";
  }
  EXPECT_ERROR_HAS(error_of(dir.write("chunks.tmx", tmx(R"(<layer name="L" width="4" height="3"><data encoding="csv">)" + chunks + "</data></layer>", kTsx, R"(infinite="1")"))),
                   "kMaxTiledMapTiles");
}

// Chunk coordinates near INT32_MAX were added to cell offsets (signed overflow); a number too
// big for an int was cast from float (undefined).
TEST(TiledHostile, ChunkCoordinatesNearIntMaxAreRefused) {
  Scratch dir;
  const std::string x = error_of(dir.write("edge.tmx", tmx(R"(<layer name="L" width="4" height="3"><data encoding="csv">
      <chunk x="2147483647" y="0" width="2" height="1">1,1</chunk></data></layer>)", kTsx, R"(infinite="1")")));
  EXPECT_ERROR_HAS(x, "<chunk");
  EXPECT_ERROR_HAS(x, "beyond 2147483647");
  const std::string big = error_of(dir.write("big.tmx", tmx(R"(<layer name="L" width="4" height="3"><data encoding="csv">
      <chunk x="1e30" y="0" width="2" height="1">1,1</chunk></data></layer>)", kTsx, R"(infinite="1")")));
  EXPECT_ERROR_HAS(big, "attribute x");
  EXPECT_ERROR_HAS(big, "outside [-2147483648, 2147483647]");
  const std::string j = error_of(dir.write("edge.tmj", R"({"type": "map", "orientation": "orthogonal", "infinite": true,
    "width": 1, "height": 1, "tilewidth": 8, "tileheight": 8, "layers": [{"type": "tilelayer", "name": "L",
    "chunks": [{"x": 0, "y": 2147483647, "width": 1, "height": 1, "data": [1]}]}]})"));
  EXPECT_ERROR_HAS(j, "chunks[0]");
  EXPECT_ERROR_HAS(j, "beyond 2147483647");
  // The last cell that still fits is fine.
  const TiledMap m = load_tiled_map(dir.write("fits.tmx", tmx(R"(<layer name="L" width="4" height="3"><data encoding="csv">
      <chunk x="2147483646" y="-2147483648" width="1" height="1">1</chunk></data></layer>)", kTsx, R"(infinite="1")")));
  ASSERT_EQ(m.colliders.size(), 1u);
  EXPECT_EQ(m.colliders[0].source.cell_x, 2147483646);
  EXPECT_TRUE(is_valid(compute_aabb(m.colliders[0].shape, m.colliders[0].transform)));
}

// An external tileset, template or map that is /dev/zero was read without end (and so were a
// scene file and an OBJ level); a huge file was read whole.
TEST(TiledHostile, EndlessOrHugeFilesAreRefusedAtTheSizeLimit) {
  if (!fs::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  Scratch dir;
  const std::string ts = error_of(dir.write("zero_tsx.tmx", tmx("", R"(<tileset firstgid="1" source="/dev/zero"/>)")));
  EXPECT_ERROR_HAS(ts, "zero_tsx.tmx: <tileset firstgid=1>: /dev/zero: file: larger than 67108864 bytes");
  EXPECT_ERROR_HAS(ts, "kMaxInputFileBytes");
  EXPECT_ERROR_HAS(error_of(dir.write("zero_tx.tmx", tmx(R"(<objectgroup name="o"><object id="1" template="/dev/zero" x="0" y="0"/></objectgroup>)"))),
                   "/dev/zero: file: larger than");
  EXPECT_ERROR_HAS(error_of(dir.write("zero.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 1, "height": 1,
    "tilewidth": 8, "tileheight": 8, "tilesets": [{"firstgid": 1, "source": "/dev/zero"}], "layers": []})")),
                   "kMaxInputFileBytes");
  EXPECT_ERROR_HAS(error_of("/dev/zero"), "kMaxInputFileBytes");
  // A regular file one byte over the limit (sparse: no disk used).
  const fs::path big = dir.write("big.tsx", "");
  fs::resize_file(big, (std::size_t{64} << 20) + 1);
  EXPECT_ERROR_HAS(error_of(dir.write("big.tmx", tmx("", R"(<tileset firstgid="1" source="big.tsx"/>)"))), "kMaxInputFileBytes");
  try {
    (void)load_scene_json("/dev/zero");
    ADD_FAILURE() << "scene from /dev/zero";
  } catch (const InvalidInput& e) {
    EXPECT_ERROR_HAS(std::string(e.what()), "kMaxInputFileBytes");
  }
  try {
    (void)io::load_obj("/dev/zero");
    ADD_FAILURE() << "OBJ from /dev/zero";
  } catch (const InvalidInput& e) {
    EXPECT_ERROR_HAS(std::string(e.what()), "kMaxInputFileBytes");
  }
}

// An external tileset used many times was read (and copied) every time: a small map could make
// the loader read gigabytes. Files are now read once per load and every use is charged.
TEST(TiledHostile, ReusedExternalFilesCountTowardsTheLoadLimit) {
  Scratch dir;
  dir.write("padded.tsx", R"(<tileset name="p" tilewidth="16" tileheight="16" tilecount="1"><!--)" +
                              std::string(std::size_t{1} << 20, 'x') + "--></tileset>");
  std::string refs;
  for (int i = 0; i < 300; ++i) refs += "<tileset firstgid=\"" + std::to_string(1 + i) + "\" source=\"padded.tsx\"/>";
  const std::string e = error_of(dir.write("reuse.tmx", tmx("", refs)));
  EXPECT_ERROR_HAS(e, "kMaxTiledLoadBytes");
  // A few uses are fine.
  EXPECT_NO_THROW((void)load_tiled_map(dir.write("few.tmx", tmx("", R"(<tileset firstgid="1" source="padded.tsx"/><tileset firstgid="2" source="padded.tsx"/>)"))));
}

// firstgid outside [1, 2^28) wrapped around (negative) or was cast from an out-of-range float.
TEST(TiledHostile, FirstGidAndTileIdsOutOfRangeAreRefused) {
  Scratch dir;
  for (const char* first : {"-5", "0", "4294967296", "268435456"}) {
    const std::string e = error_of(dir.write("first.tmx", tmx("", std::string(R"(<tileset firstgid=")") + first + R"(" name="t" tilewidth="16" tileheight="16"/>)")));
    EXPECT_ERROR_HAS(e, "attribute firstgid");
    EXPECT_ERROR_HAS(e, "outside [1, 268435455]");
  }
  EXPECT_ERROR_HAS(error_of(dir.write("first.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 1, "height": 1,
    "tilewidth": 8, "tileheight": 8, "tilesets": [{"firstgid": -1, "name": "t"}], "layers": []})")), "firstgid");
  EXPECT_ERROR_HAS(error_of(dir.write("tileid.tmx", tmx("", R"(<tileset firstgid="1" name="t" tilewidth="16" tileheight="16"><tile id="-3"><image width="4" height="4"/></tile></tileset>)"))),
                   "attribute id");
  // A gid past the tileset's tiles names the cell.
  EXPECT_ERROR_HAS(error_of(dir.write("gid.tmx", tmx(R"(<layer name="L" width="1" height="1"><data encoding="csv">9</data></layer>)"))),
                   "gid 9 is in no tileset");
  EXPECT_ERROR_HAS(error_of(dir.write("gid.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 1, "height": 1,
    "tilewidth": 8, "tileheight": 8, "layers": [{"type": "tilelayer", "name": "L", "width": 1, "height": 1, "data": [4294967296]}]})")),
                   "beyond 32 bits");
}

// Finite numbers far beyond any map (1e30) gave colliders at infinity; now refused with the range.
TEST(TiledHostile, CoordinatesBeyondTheRangeAreRefused) {
  Scratch dir;
  const std::string e = error_of(dir.write("far.tmx", tmx(R"(<objectgroup name="o"><object id="3" x="1e30" y="0" width="3e38" height="1"/></objectgroup>)")));
  EXPECT_ERROR_HAS(e, "<object id=3>");
  EXPECT_ERROR_HAS(e, "kMaxTiledCoordinate");
  EXPECT_ERROR_HAS(error_of(dir.write("far.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 1, "height": 1,
    "tilewidth": 8, "tileheight": 8, "layers": [{"type": "objectgroup", "name": "o", "offsetx": -2e7, "objects": []}]})")),
                   "offsetx: -20000000 is beyond");
  EXPECT_NO_THROW((void)load_tiled_map(dir.write("near.tmx", tmx(R"(<objectgroup name="o"><object id="3" x="9999990" y="-1e7" width="10" height="1"/></objectgroup>)"))));
}

// A polygon of a million points made convex decomposition run for hours (O(n^2) to O(n^3)).
TEST(TiledHostile, PolygonPointCountIsLimited) {
  Scratch dir;
  std::string points;
  for (std::size_t i = 0; i <= kMaxTiledPolygonPoints; ++i) points += std::to_string(i) + "," + std::to_string((i * i) % 7) + " ";
  const std::string e = error_of(dir.write("poly.tmx", tmx(R"(<objectgroup name="o"><object id="4" x="0" y="0"><polygon points=")" + points + R"("/></object></objectgroup>)")));
  EXPECT_ERROR_HAS(e, "<object id=4>");
  EXPECT_ERROR_HAS(e, "kMaxTiledPolygonPoints");
  nlohmann::json many = nlohmann::json::array();
  for (std::size_t i = 0; i <= kMaxTiledPolygonPoints; ++i) many.push_back({{"x", i}, {"y", i % 3}});
  nlohmann::json map = {{"type", "map"}, {"orientation", "orthogonal"}, {"width", 1}, {"height", 1}, {"tilewidth", 8},
                        {"tileheight", 8},
                        {"layers", {{{"type", "objectgroup"}, {"name", "o"}, {"objects", {{{"id", 5}, {"x", 0}, {"y", 0}, {"polygon", many}}}}}}}};
  EXPECT_ERROR_HAS(error_of(dir.write("poly.tmj", map.dump())), "kMaxTiledPolygonPoints");
}

// A tile with many collision shapes on a big layer multiplied into millions of colliders
// (about 1.3 KB each). Now refused past kMaxTiledColliders.
TEST(TiledHostile, ColliderCountIsLimited) {
  Scratch dir;
  std::string shapes;
  for (int i = 0; i < 64; ++i) shapes += "<object id=\"" + std::to_string(i + 1) + "\" x=\"0\" y=\"0\" width=\"1\" height=\"1\"/>";
  const std::string tileset = R"(<tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="1"><tile id="0"><objectgroup>)" +
                              shapes + "</objectgroup></tile></tileset>";
  // 16,385 cells x 64 shapes = 1,048,640 colliders, one chunk of gid 1 (csv).
  const int cells = static_cast<int>(kMaxTiledColliders / 64) + 1;
  std::string csv;
  for (int i = 0; i < cells; ++i) csv += i == 0 ? "1" : ",1";
  const std::string e = error_of(dir.write("many.tmx", tmx(R"(<layer name="L" width=")" + std::to_string(cells) +
                                                               R"(" height="1"><data encoding="csv">)" + csv + "</data></layer>", tileset)));
  EXPECT_ERROR_HAS(e, "kMaxTiledColliders");
}

// Booleans written 0/1 threw nlohmann's type_error out of the loader (not InvalidInput); names
// and values quoted in errors may hold bytes that are not UTF-8.
TEST(TiledHostile, LooseBooleansReadAndErrorsAreValidUtf8) {
  Scratch dir;
  const TiledMap m = load_tiled_map(dir.write("flag.tmj", R"({"type": "map", "orientation": "orthogonal", "infinite": 0,
    "width": 1, "height": 1, "tilewidth": 8, "tileheight": 8, "layers": [{"type": "objectgroup", "name": "o",
    "objects": [{"id": 1, "x": 0, "y": 0, "width": 4, "height": 4, "ellipse": 1}]}]})"));
  ASSERT_EQ(m.objects.size(), 1u);
  EXPECT_EQ(m.objects[0].kind, TiledShapeKind::ellipse);
  EXPECT_ERROR_HAS(error_of(dir.write("flag2.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 1, "height": 1,
    "tilewidth": 8, "tileheight": 8, "layers": [{"type": "objectgroup", "name": "o", "objects": [{"id": 1, "point": "yes"}]}]})")),
                   "point: not a boolean");
  const std::string e = error_of(dir.write("utf8.tmx", tmx("<objectgroup name=\"\xff\xfe\"><object id=\"9\" x=\"0\" y=\"0\"><polygon points=\"0,0 10,10 10,0 0,10\"/></object></objectgroup>")));
  EXPECT_ERROR_HAS(e, "\\xFF\\xFE");
  EXPECT_NO_THROW((void)nlohmann::json(e).dump());
}

}  // namespace
}  // namespace collide
