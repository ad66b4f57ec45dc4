#include <collide/core/error.hpp>
#include <collide/io/tiled.hpp>

#include "support/test_util.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <tuple>

namespace collide {
namespace {

namespace fs = std::filesystem;

const fs::path kTiled = fs::path(COLLIDE_DATA_DIR) / "tiled";

// ---- helpers ----------------------------------------------------------------------------------

std::vector<const TiledObject*> objects_in(const TiledMap& map, std::string_view layer) {
  std::vector<const TiledObject*> out;
  for (const TiledObject& o : map.objects) {
    if (o.layer == layer) out.push_back(&o);
  }
  return out;
}

int count_kind(const std::vector<const TiledObject*>& objects, TiledShapeKind kind,
               bool templated = false) {
  return static_cast<int>(std::count_if(objects.begin(), objects.end(), [&](const TiledObject* o) {
    return o->kind == kind && o->template_file.empty() != templated;
  }));
}

std::vector<const TiledCollider*> colliders_of(const TiledMap& map, int object_id) {
  std::vector<const TiledCollider*> out;
  for (const TiledCollider& c : map.colliders) {
    if (c.source.object_id == object_id && c.source.cell_x < 0) out.push_back(&c);
  }
  return out;
}

/// World vertices of a polygon or segment collider.
std::vector<Vec2> world_vertices(const TiledCollider& c) {
  std::vector<Vec2> out;
  if (const auto* p = std::get_if<Polygon>(&c.shape)) {
    for (int i = 0; i < p->count; ++i) out.push_back(transform_point(c.transform, p->vertices[i]));
  } else if (const auto* s = std::get_if<Segment>(&c.shape)) {
    out = {transform_point(c.transform, s->a), transform_point(c.transform, s->b)};
  }
  return out;
}

double polygon_area(const Polygon& p) {
  return signed_area(std::span<const Vec2>(p.vertices.data(), static_cast<size_t>(p.count)));
}

Aabb merged_aabb(const std::vector<const TiledCollider*>& cs) {
  if (cs.empty()) {
    ADD_FAILURE() << "no colliders";
    return {};
  }
  Aabb box = compute_aabb(cs.front()->shape, cs.front()->transform);
  for (const TiledCollider* c : cs) box = merge(box, compute_aabb(c->shape, c->transform));
  return box;
}

#define EXPECT_AABB_NEAR(box, lo, hi, tol) \
  do {                                    \
    EXPECT_VEC2_NEAR((box).min, lo, tol); \
    EXPECT_VEC2_NEAR((box).max, hi, tol); \
  } while (false)

/// A scratch folder for synthetic maps, removed with the test.
class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("collide_tiled_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return path_ / name;
  }

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

// ---- every shared map -------------------------------------------------------------------------

TEST(Tiled, EveryMapUnderTheDataFolderLoads) {
  int maps = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kTiled)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".tmx" && ext != ".tmj" && ext != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    TiledMap map;
    ASSERT_NO_THROW(map = load_tiled_map(entry.path()));
    ++maps;
    EXPECT_FALSE(map.colliders.empty());
    for (const TiledCollider& c : map.colliders) {
      EXPECT_TRUE(is_valid(c.transform));
      EXPECT_TRUE(is_valid(compute_aabb(c.shape, c.transform)));
      if (const auto* p = std::get_if<Polygon>(&c.shape)) {
        EXPECT_NO_THROW((void)make_convex_polygon(
            std::span<const Vec2>(p->vertices.data(), static_cast<size_t>(p->count))));
      }
    }
  }
  EXPECT_EQ(maps, 7);
}

TEST(Tiled, PlatformTmxMatchesMeasuredContents) {
  const TiledMap map = load_tiled_map(kTiled / "tmxlite/ParseTest/maps/platform.tmx");
  EXPECT_EQ(map.width, 200);
  EXPECT_EQ(map.height, 40);
  EXPECT_EQ(map.tile_size, Vec2(64.0f, 64.0f));
  const auto objects = objects_in(map, "Objects");
  ASSERT_EQ(objects.size(), 30u);
  EXPECT_EQ(count_kind(objects, TiledShapeKind::rectangle), 20);
  EXPECT_EQ(count_kind(objects, TiledShapeKind::polyline), 7);
  EXPECT_EQ(count_kind(objects, TiledShapeKind::polygon), 2);
  EXPECT_EQ(count_kind(objects, TiledShapeKind::ellipse), 1);
  size_t polyline_vertices = 0;
  for (const TiledObject* o : objects) {
    if (o->kind == TiledShapeKind::polyline) polyline_vertices += o->points.size();
    if (o->kind == TiledShapeKind::ellipse) EXPECT_NEAR(o->rotation, test::kPi / 2, 1e-6f);
    EXPECT_EQ(o->layer_offset, Vec2(1.0f, -2.0f));
  }
  EXPECT_EQ(polyline_vertices, 93u);
  // Colliders: 20 boxes, 93 - 7 links, the ellipse as one polygon, polygons in pieces.
  int segments = 0, boxes = 0;
  for (const TiledCollider& c : map.colliders) {
    if (c.source.kind == TiledShapeKind::polyline) segments += std::holds_alternative<Segment>(c.shape);
    if (c.source.kind == TiledShapeKind::rectangle) boxes += std::holds_alternative<Polygon>(c.shape);
  }
  EXPECT_EQ(segments, 86);
  EXPECT_EQ(boxes, 20);
  // The layer group's tile layers were decoded (base64 + zlib) even though they add no shapes.
  EXPECT_GT(map.tile_cells, 0);
}

TEST(Tiled, PlatformTmxObjectsLandAtHandCheckedPositions) {
  const TiledMap map = load_tiled_map(kTiled / "tmxlite/ParseTest/maps/platform.tmx");
  const Vec2 layer{1.0f, -2.0f};
  // Rectangle id 1: x=128 y=2496 2240x64.
  EXPECT_AABB_NEAR(merged_aabb(colliders_of(map, 1)), layer + Vec2(128, 2496),
                   layer + Vec2(128 + 2240, 2496 + 64), 1e-3f);
  // Ellipse id 6: 128x64 at (576, 640) rotated 90 degrees clockwise on screen about its
  // top-left corner: it now spans x in [576 - 64, 576], y in [640, 640 + 128].
  const auto ellipse = colliders_of(map, 6);
  ASSERT_EQ(ellipse.size(), 1u);
  ASSERT_TRUE(std::holds_alternative<Polygon>(ellipse[0]->shape));
  EXPECT_EQ(std::get<Polygon>(ellipse[0]->shape).count, kTiledEllipseVertices);
  EXPECT_AABB_NEAR(merged_aabb(ellipse), layer + Vec2(512, 640), layer + Vec2(576, 768), 1e-2f);
  // Polyline id 3: one link (0,0)-(64,64) from (64, 2432).
  const auto link = colliders_of(map, 3);
  ASSERT_EQ(link.size(), 1u);
  const std::vector<Vec2> ends = world_vertices(*link[0]);
  EXPECT_VEC2_NEAR(ends[0], layer + Vec2(64, 2432), 1e-3f);
  EXPECT_VEC2_NEAR(ends[1], layer + Vec2(128, 2496), 1e-3f);
  // Polygon id 8, rotated 45 degrees: each input point rotated by hand must be a piece vertex,
  // and the pieces' areas add up to the polygon's.
  const std::vector<Vec2> points{{0, 0}, {-66, 98}, {-22, 206}, {100, 234}, {226, 152}, {187, 3}};
  const float c = std::cos(test::kPi / 4), s = std::sin(test::kPi / 4);
  const auto pieces = colliders_of(map, 8);
  double area = 0.0;
  for (const TiledCollider* piece : pieces) area += polygon_area(std::get<Polygon>(piece->shape));
  EXPECT_NEAR(area, std::fabs(signed_area(points)), 1e-2);
  for (Vec2 p : points) {
    const Vec2 want = layer + Vec2(768, 1152) + Vec2(c * p.x - s * p.y, s * p.x + c * p.y);
    float best = 1e30f;
    for (const TiledCollider* piece : pieces) {
      for (Vec2 v : world_vertices(*piece)) best = std::min(best, distance(v, want));
    }
    EXPECT_LT(best, 1e-2f) << "vertex (" << p.x << ", " << p.y << ")";
  }
  // Polygon id 19 is concave: more than one piece, same area.
  const std::vector<Vec2> concave{{175, 0}, {-45, 11}, {73, 39}, {-27, 80}, {220, 128}, {128, 68}};
  const auto concave_pieces = colliders_of(map, 19);
  EXPECT_GE(concave_pieces.size(), 2u);
  area = 0.0;
  for (const TiledCollider* piece : concave_pieces) area += polygon_area(std::get<Polygon>(piece->shape));
  EXPECT_NEAR(area, std::fabs(signed_area(concave)), 1e-2);
}

TEST(Tiled, MelonJsMap1MatchesMeasuredContents) {
  const TiledMap map = load_tiled_map(kTiled / "melonjs/platformer/map/map1.tmx");
  // SOURCES.md's 17 rectangles are the whole map's: 10 in "Collision", 7 entity boxes.
  int all_rectangles = 0;
  for (const TiledObject& o : map.objects) all_rectangles += o.kind == TiledShapeKind::rectangle;
  EXPECT_EQ(all_rectangles, 17);
  const auto layer = objects_in(map, "Collision");
  EXPECT_EQ(count_kind(layer, TiledShapeKind::rectangle), 10);
  EXPECT_EQ(count_kind(layer, TiledShapeKind::polygon), 1);
  EXPECT_EQ(count_kind(layer, TiledShapeKind::polyline), 8);
  for (const TiledObject* o : layer) {
    if (o->kind == TiledShapeKind::polyline) EXPECT_EQ(o->points.size(), 2u);
    if (o->kind == TiledShapeKind::polygon) {
      EXPECT_EQ(o->points.size(), 4u);
      EXPECT_EQ(o->type, "slope");
    }
  }
}

/// The collision sets of a tileset: tile id -> shapes, to compare two files tile by tile.
std::map<int, const TiledTile*> collision_sets(const TiledTileset& ts) {
  std::map<int, const TiledTile*> out;
  for (const TiledTile& t : ts.tiles) {
    if (!t.collision.empty()) out[t.id] = &t;
  }
  return out;
}

TEST(Tiled, TilesonTmxAndJsonGiveTheSameTileCollisionSets) {
  // The .tmx names an external DTD; loading it offline proves the parser does not fetch it.
  const TiledMap xml = load_tiled_map(kTiled / "tileson/test-maps/ultimate_test.tmx");
  const TiledMap json = load_tiled_map(kTiled / "tileson/test-maps/ultimate_test.json");
  ASSERT_EQ(xml.tilesets.size(), 1u);
  ASSERT_EQ(json.tilesets.size(), 1u);
  const auto a = collision_sets(xml.tilesets[0]);
  const auto b = collision_sets(json.tilesets[0]);
  EXPECT_EQ(a.size(), 45u);
  ASSERT_EQ(a.size(), b.size());
  int rectangles = 0, polygons = 0, clockwise = 0, counter_clockwise = 0;
  for (const auto& [id, tile] : a) {
    ASSERT_TRUE(b.count(id)) << "tile " << id;
    const TiledTile& other = *b.at(id);
    ASSERT_EQ(tile->collision.size(), other.collision.size());
    for (size_t k = 0; k < tile->collision.size(); ++k) {
      const TiledObject& p = tile->collision[k];
      const TiledObject& q = other.collision[k];
      EXPECT_EQ(p.kind, q.kind);
      EXPECT_EQ(p.position, q.position);
      EXPECT_EQ(p.size, q.size);
      EXPECT_EQ(p.points, q.points);
      rectangles += p.kind == TiledShapeKind::rectangle;
      if (p.kind == TiledShapeKind::polygon) {
        ++polygons;
        (signed_area(p.points) > 0 ? counter_clockwise : clockwise)++;
      }
    }
  }
  EXPECT_EQ(rectangles, 33);
  EXPECT_EQ(polygons, 12);
  EXPECT_GT(clockwise, 0);  // both windings occur
  EXPECT_GT(counter_clockwise, 0);
  // Object layers differ between the two files (11 vs 15 tile objects); templates agree.
  const auto xo = objects_in(xml, "Object Layer");
  const auto jo = objects_in(json, "Object Layer");
  EXPECT_EQ(count_kind(xo, TiledShapeKind::tile), 11);
  EXPECT_EQ(count_kind(jo, TiledShapeKind::tile), 15);
  for (const auto* list : {&xo, &jo}) {
    EXPECT_EQ(count_kind(*list, TiledShapeKind::rectangle, true), 3);
    EXPECT_EQ(count_kind(*list, TiledShapeKind::text), 1);
    for (const TiledObject* o : *list) {
      if (!o->template_file.empty()) {
        EXPECT_EQ(o->name, "useless_template_object");
        EXPECT_EQ(o->size, Vec2(32.0f, 32.0f));
      }
    }
  }
  // Tile-layer colliders: every collider of a cell lies within its cell's box.
  for (const TiledMap* map : {&xml, &json}) {
    int cells = 0;
    for (const TiledCollider& c : map->colliders) {
      if (c.source.cell_x < 0) continue;
      ++cells;
      const Aabb box = compute_aabb(c.shape, c.transform);
      const Vec2 lo{c.source.cell_x * 16.0f, c.source.cell_y * 16.0f};
      EXPECT_TRUE(contains(fatten(Aabb{lo, lo + Vec2(16.0f)}, 1e-3f), box));
    }
    EXPECT_GT(cells, 150);
  }
}

TEST(Tiled, RaytmxExampleMatchesMeasuredContents) {
  const TiledMap map = load_tiled_map(kTiled / "raytmx/examples/assets/example.tmx");
  const TiledTileset* ruins = nullptr;
  const TiledTileset* trees = nullptr;
  for (const TiledTileset& ts : map.tilesets) {
    if (ts.name == "ruins") ruins = &ts;
    if (ts.name == "trees") trees = &ts;
  }
  ASSERT_NE(ruins, nullptr);
  ASSERT_NE(trees, nullptr);
  EXPECT_EQ(collision_sets(*ruins).size(), 37u);
  int rects = 0;
  for (const TiledTile& t : ruins->tiles) {
    for (const TiledObject& o : t.collision) rects += o.kind == TiledShapeKind::rectangle;
  }
  EXPECT_EQ(rects, 55);
  int polygons = 0, vertices = 0, concave = 0;
  for (const TiledTile& t : trees->tiles) {
    for (const TiledObject& o : t.collision) {
      ASSERT_EQ(o.kind, TiledShapeKind::polygon);
      ++polygons;
      vertices += static_cast<int>(o.points.size());
      const float area = std::fabs(signed_area(o.points));
      // The pieces this polygon became in the first cell that uses the tile: same area.
      const std::uint32_t gid = trees->first_gid + static_cast<std::uint32_t>(t.id);
      const TiledCollider* first = nullptr;
      for (const TiledCollider& c : map.colliders) {
        if ((c.source.gid & kTiledGidMask) == gid) {
          first = &c;
          break;
        }
      }
      const bool found = first != nullptr;
      double piece_area = 0.0;
      int pieces = 0;
      for (const TiledCollider& d : map.colliders) {
        if (found && d.source.gid == first->source.gid && d.source.cell_x == first->source.cell_x &&
            d.source.cell_y == first->source.cell_y) {
          piece_area += polygon_area(std::get<Polygon>(d.shape));
          ++pieces;
        }
      }
      if (found) {
        EXPECT_NEAR(piece_area, area, 1e-3 * area) << "tile " << t.id;
        concave += pieces > 1;
      }
    }
  }
  EXPECT_EQ(polygons, 6);
  EXPECT_EQ(vertices, 43);
  EXPECT_GE(concave, 1);  // the concave trees that the map uses came out in pieces
  int rectangles = 0, polys = 0, templates = 0, texts = 0;
  for (const TiledObject& o : map.objects) {
    rectangles += o.kind == TiledShapeKind::rectangle && o.template_file.empty();
    polys += o.kind == TiledShapeKind::polygon;
    templates += !o.template_file.empty();
    texts += o.kind == TiledShapeKind::text;
    if (!o.template_file.empty()) EXPECT_EQ(o.size, Vec2(16.0f, 16.0f));
  }
  EXPECT_EQ(rectangles, 19);
  EXPECT_EQ(polys, 2);
  EXPECT_EQ(templates, 3);
  EXPECT_EQ(texts, 1);
}

TEST(Tiled, RaytmxCollisionTilesGiveBoxCircleAndDiamond) {
  const TiledMap map = load_tiled_map(kTiled / "raytmx/test/assets/collision_tiles.tmx");
  int boxes = 0, circles = 0, diamonds = 0;
  for (const TiledCollider& c : map.colliders) {
    const Vec2 cell{c.source.cell_x * 16.0f, c.source.cell_y * 16.0f};
    const std::uint32_t gid = c.source.gid & kTiledGidMask;
    if (gid == 2) {  // tile 1: the full 16x16 box
      ++boxes;
      EXPECT_AABB_NEAR(compute_aabb(c.shape, c.transform), cell, cell + Vec2(16.0f), 1e-4f);
    } else if (gid == 3) {  // tile 2: a 12x12 ellipse at (2, 2): a circle of radius 6
      ++circles;
      ASSERT_TRUE(std::holds_alternative<Circle>(c.shape));
      EXPECT_NEAR(std::get<Circle>(c.shape).radius, 6.0f, 1e-5f);
      EXPECT_VEC2_NEAR(transform_point(c.transform, std::get<Circle>(c.shape).center),
                       cell + Vec2(8.0f), 1e-4f);
    } else if (gid == 4) {  // tile 3: diamond (8,1) (15,8) (8,15) (1,8)
      ++diamonds;
      EXPECT_AABB_NEAR(compute_aabb(c.shape, c.transform), cell + Vec2(1.0f), cell + Vec2(15.0f), 1e-4f);
      EXPECT_NEAR(polygon_area(std::get<Polygon>(c.shape)), 98.0, 1e-3);
    }
  }
  EXPECT_EQ(boxes, 40);
  EXPECT_EQ(circles, 18);
  EXPECT_EQ(diamonds, 16);
}

TEST(Tiled, StickerKnightTileObjectsTemplatesAndFlips) {
  const TiledMap map = load_tiled_map(kTiled / "mapeditor-tiled/sticker-knight/map/sandbox.tmx");
  ASSERT_EQ(map.objects.size(), 114u);
  int tiles = 0, flipped = 0, rotated = 0, templates = 0, rectangles = 0;
  for (const TiledObject& o : map.objects) {
    if (!o.template_file.empty()) {
      ++templates;
      continue;
    }
    tiles += o.kind == TiledShapeKind::tile;
    rectangles += o.kind == TiledShapeKind::rectangle;
    flipped += (o.gid & ~kTiledGidMask) != 0;
    rotated += o.rotation != 0.0f;
  }
  EXPECT_EQ(tiles, 103);
  EXPECT_EQ(flipped, 13);
  EXPECT_EQ(rotated, 8);
  EXPECT_EQ(templates, 9);
  EXPECT_EQ(rectangles, 2);
  // Templates: block.tx names gid 44 of ../objs.tsx, the map's first tileset (first gid 1).
  int blocks = 0;
  for (const TiledObject& o : map.objects) {
    if (o.template_file.find("block.tx") == std::string::npos) continue;
    ++blocks;
    EXPECT_EQ(o.name, "block");
    EXPECT_EQ(o.gid, 44u);
    EXPECT_EQ(o.kind, TiledShapeKind::tile);
    EXPECT_EQ(o.size, Vec2(96.0f, 96.0f));
  }
  EXPECT_GT(blocks, 0);
  // objs.tsx has no collision shapes: tile objects become boxes of their image rectangle,
  // anchored at the bottom-left corner and rotated about it.
  EXPECT_EQ(map.colliders.size(), 114u);
  const TiledObject* leaning = nullptr;
  for (const TiledObject& o : map.objects) {
    if (o.id == 107) leaning = &o;
  }
  ASSERT_NE(leaning, nullptr);
  const float angle = -10.4469f * std::numbers::pi_v<float> / 180.0f;
  const Vec2 origin{1173.54f, 1179.49f};
  const Vec2 size{920.0f, 352.0f};
  Vec2 lo{1e30f}, hi{-1e30f};
  for (Vec2 corner : {Vec2(0, 0), Vec2(size.x, 0), Vec2(size.x, -size.y), Vec2(0, -size.y)}) {
    const Vec2 w = origin + Vec2(std::cos(angle) * corner.x - std::sin(angle) * corner.y,
                                 std::sin(angle) * corner.x + std::cos(angle) * corner.y);
    lo = glm::min(lo, w);
    hi = glm::max(hi, w);
  }
  EXPECT_AABB_NEAR(merged_aabb(colliders_of(map, 107)), lo, hi, 1e-2f);
  TiledLoadOptions options;
  options.tile_object_image_boxes = false;
  EXPECT_EQ(load_tiled_map(kTiled / "mapeditor-tiled/sticker-knight/map/sandbox.tmx", options)
                .colliders.size(),
            2u);
}

// ---- synthetic maps: flips, scale, offsets, chunks ---------------------------------------------

const char* kTileset = R"(<tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="4" columns="4">
  <tile id="0"><objectgroup><object id="1" x="0" y="0" width="4" height="2"/></objectgroup></tile>
  <tile id="1"><objectgroup><object id="1" x="2" y="3"><polygon points="0,0 6,0 0,4"/></object></objectgroup></tile>
 </tileset>)";

std::string map_xml(const std::string& body, const std::string& extra = "") {
  return std::string(R"(<?xml version="1.0" encoding="UTF-8"?>
<map version="1.10" orientation="orthogonal" width="4" height="3" tilewidth="16" tileheight="16" )") +
         extra + ">\n" + kTileset + "\n" + body + "\n</map>\n";
}

/// Where Tiled's flips send a tile pixel (x, y) of a w x h tile: diagonal (swap), then
/// horizontal, then vertical, written out case by case.
Vec2 flipped_pixel(Vec2 p, std::uint32_t flags, float w, float h) {
  if (flags & kTiledFlipDiagonal) {
    p = {p.y, p.x};
    std::swap(w, h);
  }
  if (flags & kTiledFlipHorizontal) p.x = w - p.x;
  if (flags & kTiledFlipVertical) p.y = h - p.y;
  return p;
}

TEST(Tiled, TileLayerCellsApplyEveryFlipCombination) {
  TempDir dir;
  // Row 0 holds tile 2 (the triangle) with all 8 flip combinations over two rows of 4.
  std::string csv;
  for (std::uint32_t f = 0; f < 8; ++f) {
    const std::uint32_t gid = 2u | ((f & 1u) ? kTiledFlipHorizontal : 0u) |
                              ((f & 2u) ? kTiledFlipVertical : 0u) | ((f & 4u) ? kTiledFlipDiagonal : 0u);
    csv += std::to_string(gid) + ",";
  }
  csv += "0,0,0,0";
  const fs::path file = dir.write(
      "flips.tmx", map_xml(R"(<layer name="cells" width="4" height="3" offsetx="5" offsety="7"><data encoding="csv">)" +
                           csv + "</data></layer>"));
  const TiledMap map = load_tiled_map(file);
  ASSERT_EQ(map.colliders.size(), 8u);
  const std::vector<Vec2> triangle{{2, 3}, {8, 3}, {2, 7}};
  for (const TiledCollider& c : map.colliders) {
    const std::uint32_t flags = c.source.gid & ~kTiledGidMask;
    const Vec2 cell = Vec2(5, 7) + Vec2(c.source.cell_x * 16.0f, c.source.cell_y * 16.0f);
    const std::vector<Vec2> got = world_vertices(c);
    ASSERT_EQ(got.size(), 3u);
    for (Vec2 p : triangle) {
      const Vec2 want = cell + flipped_pixel(p, flags, 16, 16);
      float best = 1e30f;
      for (Vec2 v : got) best = std::min(best, distance(v, want));
      EXPECT_LT(best, 1e-4f) << "flags " << std::hex << flags;
    }
    EXPECT_NEAR(polygon_area(std::get<Polygon>(c.shape)), 12.0, 1e-4);  // still CCW
  }
}

TEST(Tiled, TileObjectsScaleFlipAndRotateAboutTheirBottomLeftCorner) {
  TempDir dir;
  const std::uint32_t gid = 1u | kTiledFlipHorizontal;
  const fs::path file = dir.write(
      "objects.tmx",
      map_xml(R"(<objectgroup name="o"><object id="3" gid=")" + std::to_string(gid) +
              R"(" x="100" y="200" width="32" height="32"/>
                 <object id="4" gid=")" + std::to_string(gid) +
              R"(" x="100" y="200" width="32" height="32" rotation="90"/></objectgroup>)"));
  const TiledMap map = load_tiled_map(file);
  // Tile 0's box x in [0, 4], y in [0, 2]; flipped horizontally in a 16 px tile: x in [12, 16];
  // scaled by 2: x in [24, 32], y in [0, 4]; moved up by the object's height (anchor is the
  // bottom-left): y in [-32, -28]; placed at (100, 200).
  EXPECT_AABB_NEAR(merged_aabb(colliders_of(map, 3)), Vec2(124, 168), Vec2(132, 172), 1e-4f);
  // Rotated 90 degrees about (100, 200): (x, y) -> (-y, x).
  EXPECT_AABB_NEAR(merged_aabb(colliders_of(map, 4)), Vec2(100 + 28, 200 + 24),
                   Vec2(100 + 32, 200 + 32), 1e-3f);
}

TEST(Tiled, NestedGroupOffsetsAddUp) {
  TempDir dir;
  const fs::path file = dir.write(
      "groups.tmx",
      map_xml(R"(<group name="outer" offsetx="10" offsety="20"><group name="inner" offsetx="-3" offsety="4">
           <objectgroup name="things" offsetx="1" offsety="2"><object id="1" x="0" y="0" width="5" height="5"/></objectgroup>
         </group></group>)"));
  const TiledMap map = load_tiled_map(file);
  ASSERT_EQ(map.objects.size(), 1u);
  EXPECT_EQ(map.objects[0].layer, "outer/inner/things");
  EXPECT_AABB_NEAR(merged_aabb(colliders_of(map, 1)), Vec2(8, 26), Vec2(13, 31), 1e-5f);
}

TEST(Tiled, InfiniteMapsReadChunks) {
  TempDir dir;
  const fs::path file = dir.write(
      "infinite.tmx", map_xml(R"(<layer name="c" width="4" height="3"><data encoding="csv">
           <chunk x="-16" y="-16" width="2" height="2">1,0,0,1</chunk>
           <chunk x="0" y="0" width="2" height="1">0,1</chunk></data></layer>)",
                              R"(infinite="1")"));
  const TiledMap map = load_tiled_map(file);
  EXPECT_TRUE(map.infinite);
  ASSERT_EQ(map.colliders.size(), 3u);
  std::vector<std::pair<int, int>> cells;
  for (const TiledCollider& c : map.colliders) cells.push_back({c.source.cell_x, c.source.cell_y});
  std::sort(cells.begin(), cells.end());
  EXPECT_EQ(cells, (std::vector<std::pair<int, int>>{{-16, -16}, {-15, -15}, {1, 0}}));
  EXPECT_AABB_NEAR(compute_aabb(map.colliders[0].shape, map.colliders[0].transform),
                   Vec2(-256, -256), Vec2(-252, -254), 1e-4f);
}

TEST(Tiled, FlipYMirrorsEveryCollider) {
  TiledMap map = load_tiled_map(kTiled / "tmxlite/ParseTest/maps/platform.tmx");
  std::vector<Aabb> before;
  for (const TiledCollider& c : map.colliders) before.push_back(compute_aabb(c.shape, c.transform));
  const float height = 40.0f * 64.0f;
  flip_y(map, height);
  for (size_t i = 0; i < map.colliders.size(); ++i) {
    const Aabb after = compute_aabb(map.colliders[i].shape, map.colliders[i].transform);
    EXPECT_NEAR(after.min.x, before[i].min.x, 1e-2f);
    EXPECT_NEAR(after.max.x, before[i].max.x, 1e-2f);
    EXPECT_NEAR(after.min.y, height - before[i].max.y, 1e-2f);
    EXPECT_NEAR(after.max.y, height - before[i].min.y, 1e-2f);
  }
}

/// Colliders reduced to comparable facts: kind of shape, world AABB, source object and cell.
std::vector<std::tuple<int, int, int, int, float, float, float, float>> summary(const TiledMap& map) {
  std::vector<std::tuple<int, int, int, int, float, float, float, float>> out;
  for (const TiledCollider& c : map.colliders) {
    const Aabb box = compute_aabb(c.shape, c.transform);
    auto r = [](float v) { return std::round(v * 1000.0f) / 1000.0f; };
    out.emplace_back(static_cast<int>(c.shape.index()), c.source.object_id, c.source.cell_x,
                     c.source.cell_y, r(box.min.x), r(box.min.y), r(box.max.x), r(box.max.y));
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Tiled, EveryTileDataEncodingGivesTheSameCells) {
  TempDir dir;
  // One 4x3 layer, gids 1 0 2 0 / 0 2 0 0 / 0 0 0 1, in each encoding Tiled writes.
  const std::vector<std::pair<std::string, std::string>> encodings{
      {R"(encoding="csv")", "1,0,2,0,\n0,2,0,0,\n0,0,0,1"},
      {R"(encoding="base64")", "AQAAAAAAAAACAAAAAAAAAAAAAAACAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAABAAAA"},
      {R"(encoding="base64" compression="zlib")", "eJxjZIAAJgYEQGYjA0YgBgAA7AAH"},
      {R"(encoding="base64" compression="gzip")", "\n   H4sIAAAAAAACA2NkgAAmBgRAZiMDRiAGANngFvEwAAAA\n  "},
      {"", R"(<tile gid="1"/><tile/><tile gid="2"/><tile/><tile/><tile gid="2"/><tile/><tile/><tile/><tile/><tile/><tile gid="1"/>)"}};
  std::vector<std::tuple<int, int, int, int, float, float, float, float>> first;
  int k = 0;
  for (const auto& [attributes, data] : encodings) {
    const fs::path file = dir.write("enc" + std::to_string(k++) + ".tmx",
                                    map_xml(R"(<layer name="L" width="4" height="3"><data )" +
                                            attributes + ">" + data + "</data></layer>"));
    const TiledMap map = load_tiled_map(file);
    EXPECT_EQ(map.tile_cells, 4) << attributes;
    if (first.empty()) {
      first = summary(map);
      EXPECT_EQ(first.size(), 4u);
    } else {
      EXPECT_EQ(summary(map), first) << attributes;
    }
  }
}

TEST(Tiled, JsonAndXmlOfTheSameMapGiveTheSameColliders) {
  TempDir dir;
  const std::uint32_t flipped = 2u | kTiledFlipVertical | kTiledFlipDiagonal;
  const fs::path xml = dir.write("same.tmx", map_xml(
      R"(<group name="g" offsetx="3" offsety="-4">
         <layer name="cells" width="4" height="3" offsetx="2" offsety="1"><data encoding="base64" compression="zlib">eJxjZIAAJgYEQGYjA0YgBgAA7AAH</data></layer>
         <objectgroup name="things">
          <object id="1" x="10" y="20" width="30" height="8" rotation="30"/>
          <object id="2" x="50" y="5" width="12" height="20"><ellipse/></object>
          <object id="3" x="70" y="70" rotation="-15"><polygon points="0,0 20,0 20,20 10,5 0,20"/></object>
          <object id="4" x="5" y="90"><polyline points="0,0 10,0 10,10"/></object>
          <object id="5" gid=")" + std::to_string(flipped) + R"(" x="100" y="100" width="32" height="16" rotation="45"/>
         </objectgroup></group>)"));
  const fs::path json = dir.write("same.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 4, "height": 3,
    "tilewidth": 16, "tileheight": 16, "infinite": false,
    "tilesets": [{"firstgid": 1, "name": "t", "tilewidth": 16, "tileheight": 16, "tilecount": 4, "tiles": [
      {"id": 0, "objectgroup": {"objects": [{"id": 1, "x": 0, "y": 0, "width": 4, "height": 2}]}},
      {"id": 1, "objectgroup": {"objects": [{"id": 1, "x": 2, "y": 3, "polygon": [{"x": 0, "y": 0}, {"x": 6, "y": 0}, {"x": 0, "y": 4}]}]}}]}],
    "layers": [{"type": "group", "name": "g", "offsetx": 3, "offsety": -4, "layers": [
      {"type": "tilelayer", "name": "cells", "width": 4, "height": 3, "offsetx": 2, "offsety": 1,
       "encoding": "base64", "compression": "zlib", "data": "eJxjZIAAJgYEQGYjA0YgBgAA7AAH"},
      {"type": "objectgroup", "name": "things", "objects": [
        {"id": 1, "x": 10, "y": 20, "width": 30, "height": 8, "rotation": 30},
        {"id": 2, "x": 50, "y": 5, "width": 12, "height": 20, "ellipse": true},
        {"id": 3, "x": 70, "y": 70, "rotation": -15, "polygon": [{"x": 0, "y": 0}, {"x": 20, "y": 0}, {"x": 20, "y": 20}, {"x": 10, "y": 5}, {"x": 0, "y": 20}]},
        {"id": 4, "x": 5, "y": 90, "polyline": [{"x": 0, "y": 0}, {"x": 10, "y": 0}, {"x": 10, "y": 10}]},
        {"id": 5, "gid": )" + std::to_string(flipped) + R"(, "x": 100, "y": 100, "width": 32, "height": 16, "rotation": 45}]}]}]})");
  const TiledMap a = load_tiled_map(xml);
  const TiledMap b = load_tiled_map(json);
  EXPECT_EQ(a.objects.size(), 5u);
  EXPECT_GE(a.colliders.size(), 12u);  // 4 cells, box, ellipse, 2+ polygon pieces, 2 links, tile
  EXPECT_EQ(summary(a), summary(b));
  for (const TiledMap* m : {&a, &b}) {
    for (const TiledObject& o : m->objects) EXPECT_EQ(o.layer, "g/things");
  }
}

TEST(Tiled, JsonTilesetsAndTemplatesServeBothMapFormats) {
  TempDir dir;
  dir.write("t.tsj", R"({"type": "tileset", "name": "t", "tilewidth": 16, "tileheight": 16, "tilecount": 4,
    "tiles": [{"id": 0, "objectgroup": {"objects": [{"id": 1, "x": 0, "y": 0, "width": 4, "height": 2}]}}]})");
  dir.write("crate.tj", R"({"type": "template", "tileset": {"firstgid": 1, "source": "t.tsj"},
    "object": {"name": "crate", "gid": 1, "width": 32, "height": 32}})");
  const fs::path xml = dir.write("m.tmx", R"(<map orientation="orthogonal" width="4" height="4" tilewidth="16" tileheight="16">
    <tileset firstgid="5" source="t.tsj"/>
    <objectgroup name="o"><object id="7" template="crate.tj" x="10" y="50"/></objectgroup></map>)");
  const fs::path json = dir.write("m.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 4, "height": 4,
    "tilewidth": 16, "tileheight": 16, "tilesets": [{"firstgid": 5, "source": "t.tsj"}],
    "layers": [{"type": "objectgroup", "name": "o", "objects": [{"id": 7, "template": "crate.tj", "x": 10, "y": 50}]}]})");
  for (const fs::path& file : {xml, json}) {
    SCOPED_TRACE(file.filename().string());
    const TiledMap map = load_tiled_map(file);
    ASSERT_EQ(map.objects.size(), 1u);
    EXPECT_EQ(map.objects[0].name, "crate");
    EXPECT_EQ(map.objects[0].gid, 5u);  // the template's gid 1 of t.tsj is gid 5 in this map
    // Tile box (0,0)-(4,2) scaled 2x, anchored at the bottom-left corner (10, 50).
    EXPECT_AABB_NEAR(merged_aabb(colliders_of(map, 7)), Vec2(10, 18), Vec2(18, 22), 1e-4f);
  }
}

// ---- malformed input ---------------------------------------------------------------------------

TEST(Tiled, MalformedFilesNameTheFileAndTheElement) {
  TempDir dir;
  auto expect_error = [&](const std::string& name, const std::string& text,
                          std::vector<std::string> parts) {
    const std::string message = error_of(dir.write(name, text));
    parts.push_back(name);
    for (const std::string& part : parts) {
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
    }
  };
  dir.write("broken.tsx", "<tileset name=\"t\" tilewidth=\"4\" tileheight=\"4\">\n <tile id=\"3\">\n  <objectgroup>\n"
                          "   <object id=\"1\" x=\"0\" y=\"0\" width=\"4\" height=\"4\">\n </tile>\n</tileset>\n");
  const std::string objects = R"(<objectgroup name="o">%</objectgroup>)";
  auto with_object = [&](const std::string& object) {
    std::string body = objects;
    body.replace(body.find('%'), 1, object);
    return map_xml(body);
  };
  expect_error("points.tmx", with_object(R"(<object id="12" x="0" y="0"><polygon points="0,0 a,b 3,4"/></object>)"),
               {"<object id=12>", "polygon points", "'a,b'"});
  expect_error("bowtie.tmx", with_object(R"(<object id="13" x="0" y="0"><polygon points="0,0 10,10 10,0 0,10"/></object>)"),
               {"<object id=13>", "self-intersecting"});
  expect_error("number.tmx", with_object(R"(<object id="14" x="1e" y="0" width="3" height="3"/>)"),
               {"<object id=14>", "attribute x"});
  expect_error("nan.tmx", with_object(R"(<object id="15" x="nan" y="0" width="3" height="3"/>)"),
               {"<object id=15>", "finite"});
  expect_error("gid.tmx", with_object(R"(<object id="16" gid="99" x="0" y="0"/>)"),
               {"<object id=16>", "gid 99"});
  // Syntax errors name the line, the column and the elements open there.
  expect_error("xml.tmx", "<map orientation=\"orthogonal\"><layer></map>",
               {"XML syntax error", "line 1, column", "inside <map> > <layer>"});
  expect_error("quote.tmx",
               "<?xml version=\"1.0\"?>\n<!-- a comment <object> -->\n<map orientation=\"orthogonal\">\n"
               " <objectgroup name=\"Walls\">\n  <object id=\"6\" x=\"0\" y=\"0\"/>\n"
               "  <object id=\"7\" x=\"1\" y=\"2\">\n   <polygon points \"0,0 1,1\"/>\n  </object>\n"
               " </objectgroup>\n</map>\n",
               {"XML syntax error", "line 7", "inside <map> > <objectgroup name=Walls> > <object id=7> > <polygon>"});
  expect_error("tsx_syntax.tmx", map_xml(R"(<tileset firstgid="1" source="broken.tsx"/>)"),
               {"<tileset firstgid=1>", "broken.tsx", "XML syntax error", "inside <tileset name=t> > <tile id=3>"});
  expect_error("iso.tmx", R"(<map orientation="isometric" width="1" height="1" tilewidth="4" tileheight="4"/>)",
               {"<map>", "isometric"});
  expect_error("tsx.tmx", map_xml(R"(<tileset firstgid="50" source="missing.tsx"/>)"), {"missing.tsx", "cannot be read"});
  expect_error("csv.tmx", map_xml(R"(<layer name="L" width="4" height="3"><data encoding="csv">1,2,x</data></layer>)"),
               {"<layer name=L>", "'x'"});
  expect_error("count.tmx", map_xml(R"(<layer name="L" width="4" height="3"><data encoding="csv">1,2</data></layer>)"),
               {"<layer name=L>", "2 tiles, expected 12"});
  expect_error("b64.tmx", map_xml(R"(<layer name="L" width="4" height="3"><data encoding="base64" compression="zlib">AAAA</data></layer>)"),
               {"<layer name=L>", "compressed tile data"});
  expect_error("zstd.tmx", map_xml(R"(<layer name="L" width="4" height="3"><data encoding="base64" compression="zstd">AAAA</data></layer>)"),
               {"<layer name=L>", "zstd"});
  expect_error("json.tmj", R"({"type": "map", "orientation": "orthogonal", "layers": [)",
               {"JSON syntax error in layers[0]", "line 1, column"});
  expect_error("jsonsyntax.tmj",
               "{\"type\": \"map\", \"orientation\": \"orthogonal\",\n \"layers\": [\n"
               "  {\"type\": \"objectgroup\", \"objects\": [{\"id\": 4, \"x\": 0}, {\"id\": 9, \"polygon\": [{\"x\": 1,, \"y\": 2}]}]}]}",
               {"JSON syntax error in layers[0].objects[1] (id=9).polygon[0]", "line 3"});
  expect_error("jsonx.tmj",
               R"({"type": "map", "orientation": "orthogonal", "width": 1, "height": 1, "tilewidth": 4, "tileheight": 4,
                   "layers": [{"type": "objectgroup", "name": "o", "objects": [{"id": 21, "x": "abc", "y": 0}]}]})",
               {"layers[0].objects[0] (id=21)", "x: not a number"});
  expect_error("jsonpoly.tmj",
               R"({"type": "map", "orientation": "orthogonal", "width": 1, "height": 1, "tilewidth": 4, "tileheight": 4,
                   "layers": [{"type": "objectgroup", "name": "o", "objects": [{"id": 22, "x": 0, "y": 0, "polygon": [{"x": 0}]}]}]})",
               {"(id=22)", "polygon"});
  // Regression: a number beyond double range is not a parse_error but an out_of_range exception
  // of nlohmann_json; it escaped the loader and terminated `collide run`.
  expect_error("jsonhuge.tmj",
               R"({"type": "map", "orientation": "orthogonal", "width": 1, "height": 1, "tilewidth": 4, "tileheight": 4,
                   "layers": [{"type": "objectgroup", "name": "o", "objects": [{"id": 23, "x": 1e400, "y": 0}]}]})",
               {"layers[0].objects[0] (id=23).x", "1e400"});
  EXPECT_NE(error_of(dir.write("nothing.tmx", "")).find("nothing.tmx"), std::string::npos);
  // Regression: a folder opens as a file on Linux and its first read threw std::ios_base::failure
  // out of the loader.
  for (const char* name : {"folder.tmx", "folder.tmj"}) {
    const fs::path folder = dir.write("x", "").parent_path() / name;
    fs::create_directories(folder);
    EXPECT_NE(error_of(folder).find(std::string(name) + ": file: cannot be read"), std::string::npos) << error_of(folder);
  }
}

}  // namespace
}  // namespace collide
