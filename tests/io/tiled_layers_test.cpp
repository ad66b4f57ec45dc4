// Which Tiled layers collide (issue 15): the layers each shared map uses and skips under the
// default rule, the rule on synthetic maps (property, class, name, groups, opting out; XML and
// both JSON property forms), and layers chosen by name (TiledLoadOptions::layers).

#include <collide/core/error.hpp>
#include <collide/io/tiled.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace collide {
namespace {

namespace fs = std::filesystem;

const fs::path kTiled = fs::path(COLLIDE_DATA_DIR) / "tiled";

/// Tile and object layers by whether they collide (groups and image layers apart).
struct Split {
  std::vector<std::string> used, skipped, images;
};

Split split(const TiledMap& map) {
  Split s;
  for (const TiledLayer& l : map.layers) {
    if (l.kind == TiledLayerKind::group) {
      EXPECT_FALSE(l.collides) << l.name;
      continue;
    }
    if (l.kind == TiledLayerKind::image) {
      EXPECT_FALSE(l.collides) << l.name;
      s.images.push_back(l.name);
      continue;
    }
    (l.collides ? s.used : s.skipped).push_back(l.name);
  }
  return s;
}

/// Every collider comes from a layer that collides, and each layer's count is its own.
void expect_colliders_only_from_used_layers(const TiledMap& map) {
  std::map<std::string, int> by_layer;
  for (const TiledCollider& c : map.colliders) ++by_layer[c.source.layer];
  for (const TiledLayer& l : map.layers) {
    const int n = by_layer.count(l.name) != 0 ? by_layer[l.name] : 0;
    if (!l.collides) {
      EXPECT_EQ(n, 0) << l.name << " is skipped but gave colliders";
    } else {
      EXPECT_EQ(l.colliders, n) << l.name;
    }
  }
}

const std::vector<std::string> kEveryStickerKnightLayer = {
    "static", "parallax clouds", "parallax background", "background", "ground", "castle",
    "castledeco", "shading", "game", "above", "bounds"};

// Every shared map under the default rule: only melonJS's map declares a collision layer (by
// its name "Collision"); the others declare nothing and keep every tile and object layer.
TEST(TiledLayers, EverySharedMapUsesAndSkipsTheLayersTheRuleSays) {
  struct Expect {
    std::string file;
    std::vector<std::string> used, skipped, images;
  };
  const std::vector<Expect> expected = {
      {"mapeditor-tiled/sticker-knight/map/sandbox.tmx", kEveryStickerKnightLayer, {}, {}},
      {"melonjs/platformer/map/map1.tmx",
       {"Collision"},
       {"Back Layer 2", "Back Layer 1", "Player", "Coins", "Slimes", "Front Layer", "Flies"},
       {"Background", "Clouds"}},
      {"raytmx/examples/assets/example.tmx",
       {"Floors/Light grass", "Floors/Ruin tiles", "Floors/Fades to black", "Floors/Ruin stairs", "Floors/Shadows 1",
        "Floors/Shadows 2", "Floors/Parallax reference quad", "Edges/Ruin ledges", "Edges/Ruin walls", "Trees/Trees 1",
        "Trees/Trees 2", "Parallaxed/Fog", "Parallaxed/Parallax reference quad", "Text", "Doors", "Walls"},
       {},
       {}},
      {"raytmx/test/assets/collision_tiles.tmx", {"Sole tile layer"}, {}, {}},
      {"tileson/test-maps/ultimate_test.tmx",
       {"Wangio", "Object Layer", "Main Layer", "Terrain testing", "Front Layer"},
       {},
       {"Background Image"}},
      {"tileson/test-maps/ultimate_test.json",
       {"Wangio", "Object Layer", "Main Layer", "Terrain testing", "Front Layer"},
       {},
       {"Background Image"}},
      {"tmxlite/ParseTest/maps/platform.tmx",
       {"TestGroup/Far", "TestGroup/Middle", "TestGroup/Near", "Objects"},
       {},
       {"Test Image Layer"}},
  };
  std::set<fs::path> covered;
  for (const Expect& e : expected) {
    SCOPED_TRACE(e.file);
    const TiledMap map = load_tiled_map(kTiled / e.file);
    const Split s = split(map);
    EXPECT_EQ(s.used, e.used);
    EXPECT_EQ(s.skipped, e.skipped);
    EXPECT_EQ(s.images, e.images);
    expect_colliders_only_from_used_layers(map);
    for (const TiledLayer& l : map.layers) {
      if (l.kind != TiledLayerKind::tile && l.kind != TiledLayerKind::object) continue;
      // A map that declares nothing says so; melonJS's says which layer it declared and how.
      if (e.skipped.empty()) {
        EXPECT_EQ(l.reason, "the map declares no collision layer, so every layer collides") << l.name;
      } else if (l.collides) {
        EXPECT_EQ(l.reason, "name contains 'collision'") << l.name;
      } else {
        EXPECT_EQ(l.reason, "not declared a collision layer (the map declares 'Collision')") << l.name;
      }
    }
    covered.insert(fs::weakly_canonical(kTiled / e.file));
  }
  // No shared map is left out of the table.
  for (const auto& entry : fs::recursive_directory_iterator(kTiled)) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".tmx" || ext == ".tmj" || ext == ".json") {
      EXPECT_EQ(covered.count(fs::weakly_canonical(entry.path())), 1u) << entry.path();
    }
  }
}

// melonJS: the entity layers (player, coins, slimes, flies) were walls before; now only the
// "Collision" layer's 19 objects are, exactly as when the layer is named by hand.
TEST(TiledLayers, MelonJsCollisionLayerAloneIsTheWorldGeometry) {
  const fs::path file = kTiled / "melonjs/platformer/map/map1.tmx";
  const TiledMap map = load_tiled_map(file);
  TiledLoadOptions named;
  named.layers = {"Collision"};
  const TiledMap by_name = load_tiled_map(file, named);
  ASSERT_EQ(map.colliders.size(), by_name.colliders.size());
  std::set<int> objects;
  for (const TiledCollider& c : map.colliders) {
    EXPECT_EQ(c.source.layer, "Collision");
    objects.insert(c.source.object_id);
  }
  EXPECT_EQ(objects.size(), 19u);  // 10 rectangles, 1 polygon, 8 polylines (SOURCES.md)
  for (const TiledLayer& l : map.layers) {
    if (l.name == "Player") EXPECT_EQ(l.objects, 4);
    if (l.name == "Front Layer") EXPECT_EQ(l.cells, 40);
  }
}

// The sticker-knight sandbox: its art (clouds, background, castle, shading, light) is made of
// tile objects without collision shapes; naming the ground and the map's edges keeps the
// decorations out. The ground and bounds objects are the ones that carry bodyType=static.
TEST(TiledLayers, StickerKnightWithGroundAndBoundsSkipsTheDecorations) {
  TiledLoadOptions options;
  options.layers = {"ground", "bounds"};
  const TiledMap map = load_tiled_map(kTiled / "mapeditor-tiled/sticker-knight/map/sandbox.tmx", options);
  const Split s = split(map);
  EXPECT_EQ(s.used, (std::vector<std::string>{"ground", "bounds"}));
  EXPECT_EQ(s.skipped, (std::vector<std::string>{"static", "parallax clouds", "parallax background", "background", "castle",
                                                 "castledeco", "shading", "game", "above"}));
  expect_colliders_only_from_used_layers(map);
  EXPECT_EQ(map.colliders.size(), 35u + 2u);  // one image box per ground tile object, two edges
  for (const TiledLayer& l : map.layers) {
    EXPECT_EQ(l.reason, l.collides ? "named in layers" : "not named in layers") << l.name;
    if (l.name == "shading") EXPECT_EQ(l.objects, 17);
  }
  // The objects are all still listed, as the file describes them.
  EXPECT_EQ(map.objects.size(), load_tiled_map(kTiled / "mapeditor-tiled/sticker-knight/map/sandbox.tmx").objects.size());
}

TEST(TiledLayers, AnUnknownLayerNameIsAnErrorListingTheMapsLayers) {
  TiledLoadOptions options;
  options.layers = {"ground", "clouds"};
  try {
    (void)load_tiled_map(kTiled / "mapeditor-tiled/sticker-knight/map/sandbox.tmx", options);
    FAIL() << "an unknown layer was accepted";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("sandbox.tmx: layers: 'clouds' is no layer of the map (its layers: 'static', 'parallax clouds', "
                        "'parallax background', 'background', 'ground', 'castle', 'castledeco', 'shading', 'game', "
                        "'above', 'bounds')"),
              std::string::npos)
        << what;
  }
}

// ---- the rule on synthetic maps ---------------------------------------------------------------

/// A scratch folder for synthetic maps, removed with the test.
class Scratch {
 public:
  Scratch() : path_(fs::temp_directory_path() / ("collide_tiled_layers_" + std::string(::testing::UnitTest::GetInstance()
                                                                                            ->current_test_info()
                                                                                            ->name()))) {
    fs::create_directories(path_);
  }
  ~Scratch() { fs::remove_all(path_); }
  [[nodiscard]] fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return path_ / name;
  }

 private:
  fs::path path_;
};

const char* kTileset = R"(<tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="4" columns="4">
  <tile id="0"><objectgroup><object id="1" x="0" y="0" width="16" height="16"/></objectgroup></tile>
 </tileset>)";

std::string box(int id, int x) {
  return R"(<object id=")" + std::to_string(id) + R"(" x=")" + std::to_string(x) + R"(" y="0" width="8" height="8"/>)";
}

std::string map_xml(const std::string& layers) {
  return std::string(R"(<?xml version="1.0" encoding="UTF-8"?>
<map version="1.10" orientation="orthogonal" width="4" height="1" tilewidth="16" tileheight="16">)") +
         kTileset + "\n" + layers + "\n</map>\n";
}

/// name -> (collides, reason) of the tile and object layers.
std::map<std::string, std::pair<bool, std::string>> verdicts(const TiledMap& map) {
  std::map<std::string, std::pair<bool, std::string>> out;
  for (const TiledLayer& l : map.layers) {
    if (l.kind == TiledLayerKind::tile || l.kind == TiledLayerKind::object) out[l.name] = {l.collides, l.reason};
  }
  return out;
}

// A layer, a group's class, a name and properties: each kind of declaration, and a property
// that turns a layer off inside a declared group. Undeclared layers are skipped.
TEST(TiledLayers, DeclaredLayersAloneCollideWhenAMapDeclaresAny) {
  Scratch dir;
  const fs::path file = dir.write("declared.tmx", map_xml(R"(
 <group name="level" class="Solid">
  <layer name="walls" width="4" height="1"><data encoding="csv">1,1,0,0</data></layer>
  <objectgroup name="props"><properties><property name="collides" type="bool" value="false"/></properties>)" +
                                                            box(1, 0) + R"(</objectgroup>
 </group>
 <objectgroup name="deco">)" + box(2, 0) + R"(</objectgroup>
 <objectgroup name="Collision shapes">)" + box(3, 20) + R"(</objectgroup>
 <objectgroup name="ledges"><properties><property name="Collidable" type="bool" value="true"/></properties>)" +
                                                            box(4, 40) + R"(</objectgroup>
 <objectgroup name="hud"><properties><property name="nocollide" value=""/></properties>)" + box(5, 0) + R"(</objectgroup>
 <imagelayer name="sky"/>)"));
  const TiledMap map = load_tiled_map(file);
  const auto v = verdicts(map);
  const std::string declared = "'level/walls', 'Collision shapes', 'ledges'";
  EXPECT_EQ(v.at("level/walls"), std::pair(true, std::string("class 'Solid' on group 'level'")));
  EXPECT_EQ(v.at("level/props"), std::pair(false, std::string("property collides=false")));
  EXPECT_EQ(v.at("deco"), std::pair(false, "not declared a collision layer (the map declares " + declared + ")"));
  EXPECT_EQ(v.at("Collision shapes"), std::pair(true, std::string("name contains 'collision'")));
  EXPECT_EQ(v.at("ledges"), std::pair(true, std::string("property Collidable=true")));
  EXPECT_EQ(v.at("hud"), std::pair(false, std::string("property nocollide")));
  expect_colliders_only_from_used_layers(map);
  std::map<std::string, int> by_layer;
  for (const TiledCollider& c : map.colliders) ++by_layer[c.source.layer];
  EXPECT_EQ(by_layer, (std::map<std::string, int>{{"level/walls", 2}, {"Collision shapes", 1}, {"ledges", 1}}));
  for (const TiledLayer& l : map.layers) {
    if (l.name == "level") EXPECT_EQ(l.kind, TiledLayerKind::group);
    if (l.name == "level/walls") EXPECT_EQ(l.parent, 0);
    if (l.name == "sky") EXPECT_EQ(l.kind, TiledLayerKind::image);
  }
}

// A map whose only say is "this layer does not collide" keeps every other layer.
TEST(TiledLayers, OptingOutAloneKeepsEveryOtherLayer) {
  Scratch dir;
  const fs::path file = dir.write("opt_out.tmx", map_xml(R"(
 <group name="art"><properties><property name="collision" type="bool" value="false"/></properties>
  <objectgroup name="trees">)" + box(1, 0) + R"(</objectgroup>
  <objectgroup name="rocks"><properties><property name="collides" type="bool" value="true"/></properties>)" +
                                                         box(2, 20) + R"(</objectgroup>
 </group>
 <objectgroup name="walls">)" + box(3, 40) + R"(</objectgroup>)"));
  const auto v = verdicts(load_tiled_map(file));
  // The nearest say wins: "rocks" turns itself on inside a group that is off, and so declares
  // itself; "walls" is then undeclared.
  EXPECT_EQ(v.at("art/trees"), std::pair(false, std::string("property collision=false on group 'art'")));
  EXPECT_EQ(v.at("art/rocks"), std::pair(true, std::string("property collides=true")));
  EXPECT_EQ(v.at("walls").first, false);
  const fs::path only_off = dir.write("only_off.tmx", map_xml(R"(
 <objectgroup name="trees"><properties><property name="collides" type="bool" value="false"/></properties>)" +
                                                                box(1, 0) + R"(</objectgroup>
 <objectgroup name="walls">)" + box(3, 40) + R"(</objectgroup>)"));
  const auto w = verdicts(load_tiled_map(only_off));
  EXPECT_EQ(w.at("trees"), std::pair(false, std::string("property collides=false")));
  EXPECT_EQ(w.at("walls"), std::pair(true, std::string("the map declares no collision layer, so every layer collides")));
}

// The JSON side: a layer class (Tiled >= 1.9), properties as a list (Tiled >= 1.2) and as an
// object (older maps) decide as in XML.
TEST(TiledLayers, JsonMapsDeclareLayersTheSameWay) {
  Scratch dir;
  const std::string object = R"({"id": 1, "x": 0, "y": 0, "width": 8, "height": 8})";
  const fs::path file = dir.write("declared.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 4, "height": 1,
    "tilewidth": 16, "tileheight": 16, "tilesets": [], "layers": [
      {"type": "objectgroup", "name": "ground", "class": "collision", "objects": [)" + object + R"(]},
      {"type": "group", "name": "g", "properties": [{"name": "collides", "type": "bool", "value": true}], "layers": [
        {"type": "objectgroup", "name": "inner", "objects": [)" + object + R"(]}]},
      {"type": "objectgroup", "name": "old", "properties": {"collides": false}, "objects": [)" + object + R"(]},
      {"type": "objectgroup", "name": "spawns", "objects": [)" + object + R"(]},
      {"type": "imagelayer", "name": "sky"}]})");
  const TiledMap map = load_tiled_map(file);
  const auto v = verdicts(map);
  EXPECT_EQ(v.at("ground"), std::pair(true, std::string("class 'collision'")));
  EXPECT_EQ(v.at("g/inner"), std::pair(true, std::string("property collides=true on group 'g'")));
  EXPECT_EQ(v.at("old"), std::pair(false, std::string("property collides=false")));
  EXPECT_FALSE(v.at("spawns").first);
  EXPECT_EQ(map.colliders.size(), 2u);
  ASSERT_EQ(map.layers.size(), 6u);
  EXPECT_EQ(map.layers[0].type, "collision");
  ASSERT_EQ(map.layers[3].properties.size(), 1u);
  EXPECT_EQ(map.layers[3].properties[0].name, "collides");
  EXPECT_EQ(map.layers[3].properties[0].type, "bool");
  EXPECT_EQ(map.layers[3].properties[0].value, "false");
  EXPECT_EQ(map.layers[5].kind, TiledLayerKind::image);
}

// Names override the declarations; a group's name takes every layer in it.
TEST(TiledLayers, NamedLayersOverrideDeclarationsAndAGroupTakesItsLayers) {
  Scratch dir;
  const fs::path file = dir.write("named.tmx", map_xml(R"(
 <objectgroup name="Collision">)" + box(1, 0) + R"(</objectgroup>
 <group name="art"><objectgroup name="trees">)" + box(2, 20) + R"(</objectgroup>
  <group name="deep"><layer name="tiles" width="4" height="1"><data encoding="csv">0,0,1,0</data></layer></group></group>)"));
  TiledLoadOptions options;
  options.layers = {"art"};
  const TiledMap map = load_tiled_map(file, options);
  const auto v = verdicts(map);
  EXPECT_EQ(v.at("Collision"), std::pair(false, std::string("not named in layers")));
  EXPECT_EQ(v.at("art/trees"), std::pair(true, std::string("named in layers")));
  EXPECT_EQ(v.at("art/deep/tiles"), std::pair(true, std::string("named in layers")));
  std::map<std::string, int> by_layer;
  for (const TiledCollider& c : map.colliders) ++by_layer[c.source.layer];
  EXPECT_EQ(by_layer, (std::map<std::string, int>{{"art/trees", 1}, {"art/deep/tiles", 1}}));
}

}  // namespace
}  // namespace collide
