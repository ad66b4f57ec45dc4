#include <collide/core/error.hpp>
#include <collide/decompose/convex_decomposition.hpp>

#include "support/random.hpp"
#include "support/test_util.hpp"

#include <algorithm>
#include <array>
#include <functional>
#include <limits>
#include <map>

namespace collide {
namespace {

// ---- independent truths ---------------------------------------------------------------------

/// Crossing-number point-in-polygon for any simple polygon, either winding (Haines 1994).
bool inside_polygon(std::span<const Vec2> poly, Vec2 p) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 a = poly[i], b = poly[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) {
      in = !in;
    }
  }
  return in;
}

double distance_to_outline(std::span<const Vec2> poly, Vec2 p) {
  double best = std::numeric_limits<double>::max();
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
    const float t = std::clamp(dot(p - a, b - a) / length_squared(b - a), 0.0f, 1.0f);
    best = std::min(best, static_cast<double>(distance(p, a + t * (b - a))));
  }
  return best;
}

std::span<const Vec2> vertices_of(const Polygon& p) {
  return {p.vertices.data(), static_cast<size_t>(p.count)};
}

/// Checks everything a decomposition promises: valid convex CCW pieces, areas add up, and
/// sampled points inside the input lie in exactly one piece, outside points in none.
/// Returns the number of sampled points that were inside the input.
int check_decomposition(std::span<const Vec2> input, const std::vector<Polygon>& pieces,
                        std::mt19937& rng, int samples = 400) {
  double piece_area = 0.0;
  for (const Polygon& piece : pieces) {
    EXPECT_GE(piece.count, 3);
    EXPECT_LE(piece.count, kMaxPolygonVertices);
    for (int i = 0; i < piece.count; ++i) {
      EXPECT_GT(cross(piece.vertex(i + 1) - piece.vertex(i), piece.vertex(i + 2) - piece.vertex(i + 1)),
                0.0f)
          << "piece corner not a strict left turn";
    }
    EXPECT_NO_THROW((void)make_convex_polygon(vertices_of(piece)));
    piece_area += signed_area(vertices_of(piece));
  }
  const double area = std::fabs(signed_area(input));
  EXPECT_NEAR(piece_area, area, 1e-4 * area);

  Vec2 lo = input[0], hi = input[0];
  for (Vec2 v : input) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const float size = std::max(hi.x - lo.x, hi.y - lo.y);
  int inside = 0;
  for (int s = 0; s < samples; ++s) {
    const Vec2 p{test::uniform(rng, lo.x, hi.x), test::uniform(rng, lo.y, hi.y)};
    if (distance_to_outline(input, p) < 1e-4 * size) continue;  // boundary: either answer
    const bool in = inside_polygon(input, p);
    int covering = 0;
    for (const Polygon& piece : pieces) {
      if (inside_polygon(vertices_of(piece), p)) ++covering;
    }
    if (in) ++inside;
    EXPECT_EQ(covering, in ? 1 : 0) << "point (" << p.x << ", " << p.y << ")";
  }
  return inside;
}

/// The fewest convex pieces any diagonal decomposition (no Steiner points) of the simple CCW
/// polygon can have, by brute force: every triangulation, and for each every subset of its
/// diagonals to keep (an optimal convex partition coarsens some triangulation). Small n only.
int optimum_pieces(std::span<const Vec2> poly) {
  const int n = static_cast<int>(poly.size());
  auto proper_cross = [](Vec2 p1, Vec2 p2, Vec2 q1, Vec2 q2) {
    auto o = [](Vec2 a, Vec2 b, Vec2 c) { return cross(b - a, c - a); };
    const float d1 = o(q1, q2, p1), d2 = o(q1, q2, p2), d3 = o(p1, p2, q1), d4 = o(p1, p2, q2);
    const bool straddle = ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) &&
                          ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
    auto on = [](Vec2 a, Vec2 b, Vec2 p, float d) {
      return d == 0.0f && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
             std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
    };
    return straddle || on(q1, q2, p1, d1) || on(q1, q2, p2, d2) || on(p1, p2, q1, d3) ||
           on(p1, p2, q2, d4);
  };
  auto valid = [&](int i, int j) {  // edge of the polygon, or diagonal inside it
    if ((i + 1) % n == j || (j + 1) % n == i) return true;
    for (int k = 0; k < n; ++k) {
      const int l = (k + 1) % n;
      if (k == i || k == j || l == i || l == j) continue;
      if (proper_cross(poly[i], poly[j], poly[k], poly[l])) return false;
    }
    // Edges through i or j could still overlap it when collinear; the midpoint test with a
    // vertex-free segment settles inside versus outside.
    for (int k = 0; k < n; ++k) {
      if (k == i || k == j) continue;
      const Vec2 a = poly[i], b = poly[j], p = poly[k];
      if (cross(b - a, p - a) == 0.0f && dot(p - a, b - a) > 0 && dot(p - b, a - b) > 0) return false;
    }
    return inside_polygon(poly, 0.5f * (poly[i] + poly[j]));
  };
  std::vector<std::vector<bool>> ok(n, std::vector<bool>(n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) ok[i][j] = i != j && valid(i, j);

  int best = n;  // n - 2 triangles is always possible
  std::vector<TriangleIndices> tris;
  std::function<void(std::vector<std::pair<int, int>>)> expand;
  // Enumerate triangulations: a stack of sub-chains (i, j) still to triangulate.
  expand = [&](std::vector<std::pair<int, int>> todo) {
    if (todo.empty()) {
      std::vector<std::pair<int, int>> diagonals;
      for (const auto& t : tris)
        for (int k = 0; k < 3; ++k) {
          const int a = t[k], b = t[(k + 1) % 3];
          if (a < b && !((a + 1) % n == b || (b + 1) % n == a)) diagonals.push_back({a, b});
        }
      const int m = static_cast<int>(diagonals.size());
      for (int mask = 0; mask < (1 << m); ++mask) {  // mask: diagonals removed
        const int pieces = static_cast<int>(tris.size()) - std::popcount(static_cast<unsigned>(mask));
        if (pieces >= best) continue;
        // Union-find triangles across removed diagonals, then check each region convex.
        std::vector<int> parent(tris.size());
        for (size_t t = 0; t < tris.size(); ++t) parent[t] = static_cast<int>(t);
        std::function<int(int)> find = [&](int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
        std::map<std::pair<int, int>, int> edge_tri;
        for (size_t t = 0; t < tris.size(); ++t)
          for (int k = 0; k < 3; ++k) edge_tri[{tris[t][k], tris[t][(k + 1) % 3]}] = static_cast<int>(t);
        for (int d = 0; d < m; ++d)
          if (mask & (1 << d)) {
            const auto [a, b] = diagonals[d];
            parent[find(edge_tri[{a, b}])] = find(edge_tri[{b, a}]);
          }
        std::map<int, std::map<int, int>> boundary;  // region -> from -> to
        for (size_t t = 0; t < tris.size(); ++t)
          for (int k = 0; k < 3; ++k) {
            const int a = tris[t][k], b = tris[t][(k + 1) % 3];
            const auto other = edge_tri.find({b, a});
            if (other != edge_tri.end() && find(other->second) == find(static_cast<int>(t))) continue;
            boundary[find(static_cast<int>(t))][a] = b;
          }
        bool convex = true;
        for (auto& [region, next] : boundary) {
          for (auto [from, to] : next) {
            const int after = next[to];
            if (cross(poly[to] - poly[from], poly[after] - poly[to]) < 0.0f) convex = false;
          }
        }
        if (convex) best = pieces;
      }
      return;
    }
    auto [i, j] = todo.back();
    todo.pop_back();
    if (j - i < 2) {
      expand(todo);
      return;
    }
    for (int k = i + 1; k < j; ++k) {
      if (!ok[i][k] || !ok[k][j]) continue;
      auto next = todo;
      next.push_back({i, k});
      next.push_back({k, j});
      tris.push_back({i, k, j});
      expand(next);
      tris.pop_back();
    }
  };
  expand({{0, n - 1}});
  return best;
}

std::vector<Vec2> moved(std::span<const Vec2> pts, const Transform& xf) {
  std::vector<Vec2> out;
  for (Vec2 p : pts) out.push_back(transform_point(xf, p));
  return out;
}

std::vector<Vec2> reversed(std::vector<Vec2> pts) {
  std::reverse(pts.begin(), pts.end());
  return pts;
}

/// Star-shaped random polygon: sorted angles, random radii; simple by construction.
std::vector<Vec2> random_star_shaped(std::mt19937& rng, int n, float size) {
  std::vector<float> angles;
  for (int i = 0; i < n; ++i) angles.push_back(test::uniform(rng, 0.0f, 2.0f * test::kPi));
  std::sort(angles.begin(), angles.end());
  std::vector<Vec2> pts;
  for (float a : angles) {
    const float r = size * test::uniform(rng, 0.2f, 1.0f);
    pts.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return pts;
}

// ---- hand cases with known optimum ------------------------------------------------------------

const std::vector<Vec2> kLShape{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
const std::vector<Vec2> kUShape{{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};

std::vector<Vec2> comb(int teeth) {  // base strip with `teeth` rectangular teeth on top
  std::vector<Vec2> pts{{0, 0}, {static_cast<float>(2 * teeth - 1), 0}};
  for (int t = teeth - 1; t >= 0; --t) {
    const float x = static_cast<float>(2 * t);
    pts.push_back({x + 1, 3});
    pts.push_back({x, 3});
    if (t > 0) {
      pts.push_back({x, 1});
      pts.push_back({x - 1, 1});
    }
  }
  // Right edge of the last tooth rises from the base corner: fix the first tooth's outline.
  pts[2] = {static_cast<float>(2 * teeth - 1), 3};
  return pts;
}

std::vector<Vec2> star(int points, float outer, float inner) {
  std::vector<Vec2> pts;
  for (int i = 0; i < 2 * points; ++i) {
    const float a = test::kPi * static_cast<float>(i) / static_cast<float>(points);
    const float r = i % 2 == 0 ? outer : inner;
    pts.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return pts;
}

TEST(ConvexDecomposition, ConvexInputIsOnePiece) {
  const std::vector<Vec2> square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_EQ(decompose_convex(square).size(), 1u);
  EXPECT_EQ(decompose_convex(reversed(square)).size(), 1u);
  std::mt19937 rng(3);
  const Polygon p = test::random_polygon(rng, 40, 5.0f);
  EXPECT_EQ(decompose_convex(vertices_of(p)).size(), 1u);
}

TEST(ConvexDecomposition, HandCasesMatchBruteForceOptimum) {
  struct Case {
    const char* name;
    std::vector<Vec2> pts;
    int known_optimum;  // -1: only the brute force knows
  };
  const std::vector<Case> cases{{"L", kLShape, 2},
                                {"U", kUShape, 3},
                                {"comb3", comb(3), -1},
                                {"star5", star(5, 2.0f, 0.8f), -1},
                                {"star4", star(4, 2.0f, 0.6f), -1}};
  std::mt19937 rng(11);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const int optimum = optimum_pieces(make_simple_outline(c.pts).vertices);
    if (c.known_optimum > 0) {
      EXPECT_EQ(optimum, c.known_optimum) << "brute force disagrees with the hand count";
    }
    for (const auto& pts : {c.pts, reversed(c.pts)}) {
      const std::vector<Polygon> pieces = decompose_convex(pts, c.name);
      check_decomposition(pts, pieces, rng);
      const int count = static_cast<int>(pieces.size());
      EXPECT_GE(count, optimum);
      EXPECT_LE(count, 4 * optimum) << "Hertel-Mehlhorn bound";
      RecordProperty(std::string(c.name) + "_pieces", count);
      RecordProperty(std::string(c.name) + "_optimum", optimum);
      std::printf("%-6s pieces %d optimum %d\n", c.name, count, optimum);
    }
  }
  // The two cases whose optimum H-M reaches by any triangulation order.
  EXPECT_EQ(decompose_convex(kLShape).size(), 2u);
  EXPECT_EQ(decompose_convex(kUShape).size(), 3u);
}

TEST(ConvexDecomposition, RandomSmallPolygonsNearOptimum) {
  std::mt19937 rng(2024);
  int total = 0, total_optimum = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 5 + static_cast<int>(rng() % 5);  // 5..9 vertices: brute force is cheap
    const std::vector<Vec2> pts = random_star_shaped(rng, n, 3.0f);
    SimpleOutline outline;
    try {
      outline = make_simple_outline(pts);
    } catch (const InvalidInput&) {
      continue;
    }
    const std::vector<Polygon> pieces = decompose_convex(pts);
    check_decomposition(pts, pieces, rng, 100);
    const std::vector<Polygon> one = decompose_convex(pts, "one", 1);
    check_decomposition(pts, one, rng, 50);
    EXPECT_LE(pieces.size(), one.size()) << "more triangulations never give more pieces";
    // The public steps (edge partners found by search) agree with the fused path (partners
    // recorded while cutting ears).
    const std::vector<TriangleIndices> triangles = triangulate_ear_clipping(outline.vertices);
    EXPECT_EQ(triangles.size(), outline.vertices.size() - 2);
    EXPECT_EQ(merge_hertel_mehlhorn(outline.vertices, triangles).size(), one.size());
    const int optimum = optimum_pieces(outline.vertices);
    EXPECT_GE(static_cast<int>(pieces.size()), optimum);
    EXPECT_LE(static_cast<int>(pieces.size()), 4 * optimum);
    total += static_cast<int>(pieces.size());
    total_optimum += optimum;
  }
  std::printf("random 5..9-gons: %d pieces against an optimum of %d\n", total, total_optimum);
  EXPECT_LE(total * 20, total_optimum * 21) << "more than 5% above the optimum";
  EXPECT_LE(total, total_optimum * 3 / 2) << "far from optimal on average";
}

TEST(ConvexDecomposition, RandomStarShapedPolygonsBothWindings) {
  std::mt19937 rng(77);
  int inside = 0, sampled_polys = 0;
  for (int trial = 0; trial < 150; ++trial) {
    const int n = 3 + static_cast<int>(rng() % 60);
    std::vector<Vec2> pts = random_star_shaped(rng, n, 10.0f);
    if (trial % 2 == 1) pts = reversed(pts);
    std::vector<Polygon> pieces;
    try {
      pieces = decompose_convex(pts, "random");
    } catch (const InvalidInput& e) {
      // Only near-duplicate angles can make a degenerate draw; they must say so.
      EXPECT_NE(std::string(e.what()).find("random: "), std::string::npos);
      continue;
    }
    ++sampled_polys;
    inside += check_decomposition(pts, pieces, rng, 150);
  }
  EXPECT_GE(sampled_polys, 140);
  EXPECT_GT(inside, 1000);  // both inside and outside samples were exercised
}

TEST(ConvexDecomposition, InvariantUnderRigidTransformsAndFarFromOrigin) {
  std::mt19937 rng(5);
  for (const auto& shape : {kLShape, kUShape, comb(4), star(6, 3.0f, 1.0f)}) {
    const size_t count = decompose_convex(shape).size();
    for (int k = 0; k < 10; ++k) {
      Transform xf = test::random_transform(rng, 10.0f);
      if (k % 2 == 0) xf.p += Vec2{1e4f, -1e4f};
      const std::vector<Vec2> pts = moved(shape, xf);
      const std::vector<Polygon> pieces = decompose_convex(pts);
      if (k % 2 == 0) {
        // At 1e4 a float keeps ~1e-3 absolute, 1e-4 of these shapes' size: which corners are
        // exactly straight (the comb's) is lost, so a few more pieces are allowed; the
        // decomposition must still be exact.
        EXPECT_LE(pieces.size(), 2 * count);
      } else {
        EXPECT_EQ(pieces.size(), count);
      }
      check_decomposition(pts, pieces, rng, 100);
    }
  }
}

TEST(ConvexDecomposition, CollinearAndDuplicatePointsAreRemovedFirst) {
  // L-shape with a repeated vertex, a closing copy of the first vertex, and points on edges.
  const std::vector<Vec2> pts{{0, 0}, {1, 0}, {2, 0}, {2, 0}, {2, 1}, {1.5f, 1}, {1, 1},
                              {1, 2}, {0, 2}, {0, 1}, {0, 0}};
  const SimpleOutline outline = make_simple_outline(pts);
  EXPECT_EQ(outline.vertices.size(), 6u);
  EXPECT_FALSE(outline.reversed);
  std::mt19937 rng(1);
  const std::vector<Polygon> pieces = decompose_convex(pts);
  EXPECT_EQ(pieces.size(), 2u);
  check_decomposition(pts, pieces, rng);
  EXPECT_TRUE(make_simple_outline(reversed(pts)).reversed);
}

TEST(ConvexDecomposition, ManyVertexPiecesStayWithinTheLimit) {
  // A 200-gon whose convex part alone exceeds kMaxPolygonVertices: a circle with one notch.
  std::vector<Vec2> pts;
  for (int i = 0; i < 200; ++i) {
    const float a = 2.0f * test::kPi * static_cast<float>(i) / 200.0f;
    const float r = i == 0 ? 2.0f : 10.0f;
    pts.push_back({r * std::cos(a), r * std::sin(a)});
  }
  std::mt19937 rng(9);
  const std::vector<Polygon> pieces = decompose_convex(pts);
  EXPECT_GE(pieces.size(), 4u);
  check_decomposition(pts, pieces, rng);
}

TEST(ConvexDecomposition, RejectsBadInputNamingThePolygon) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  auto message = [](const std::vector<Vec2>& pts) {
    try {
      (void)decompose_convex(pts, "level.tmx object 12");
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto expect_has = [](const std::string& text, const char* part) {
    EXPECT_NE(text.find(part), std::string::npos) << text;
    EXPECT_EQ(text.rfind("level.tmx object 12: ", 0), 0u) << text;
  };
  expect_has(message({{0, 0}, {1, nan}, {1, 1}}), "vertex 1: not finite");
  EXPECT_THROW((void)decompose_convex(kLShape, "L", 0), InvalidInput);
  expect_has(message({{0, 0}, {1, 0}}), "at least 3");
  expect_has(message({{0, 0}, {1, 0}, {1, 0}, {0, 0}}), "fewer than 3 distinct");
  expect_has(message({{0, 0}, {1, 1}, {2, 2}, {3, 3}}), "zero area");
  expect_has(message({{0, 0}, {2, 2}, {2, 0}, {0, 2}}), "self-intersecting");  // bow tie
  expect_has(message({{0, 0}, {4, 0}, {4, 4}, {2, 4}, {2, 6}, {2, 4}, {0, 4}}), "self-intersecting");
  // Touching at a vertex (two squares joined at a corner through a shared point).
  expect_has(message({{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {1, 2}, {1, 1}, {0, 1}}),
             "self-intersecting");
  // A 5-point pentagram drawn as 5 vertices crosses itself.
  std::vector<Vec2> pentagram;
  for (int i = 0; i < 5; ++i) {
    const float a = 4.0f * test::kPi * static_cast<float>(i) / 5.0f;
    pentagram.push_back({std::cos(a), std::sin(a)});
  }
  expect_has(message(pentagram), "edge");
}

// ---- planar polygons in 3D (a level mesh's n-gon faces) ---------------------------------------

/// A 2D outline placed in a plane of 3D: corner (x, y) at origin + x e1 + y e2.
struct Embedding {
  Vec3 origin{0.0f};
  Vec3 e1{1, 0, 0};
  Vec3 e2{0, 0, -1};  // with e1: the xz floor, counter-clockwise seen from +y
  float scale = 1.0f;
  [[nodiscard]] Vec3 place(Vec2 p) const { return origin + scale * (p.x * e1 + p.y * e2); }
};

std::vector<Vec3> placed(std::span<const Vec2> poly, const Embedding& at) {
  std::vector<Vec3> out;
  for (Vec2 p : poly) out.push_back(at.place(p));
  return out;
}

/// Twice the signed area of a 2D outline by the shoelace formula, in double.
double shoelace(std::span<const Vec2> poly) {
  double a = 0.0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2 u = poly[i], v = poly[(i + 1) % poly.size()];
    a += static_cast<double>(u.x) * v.y - static_cast<double>(u.y) * v.x;
  }
  return a;
}

/// Checks a triangulation of the 3D polygon `pts`, which lies in the plane of `at` (up to float
/// rounding), against truths independent of the code under test: `expected` triangles, each of
/// three distinct corners of the polygon, wound as the polygon (the 3D normal on the side of
/// e1 x e2 when the polygon is counter-clockwise in (e1, e2)); their areas in the plane (3D cross
/// products, double) add up to the polygon's (shoelace on its corners in (e1, e2)); each lies
/// inside the polygon (its centroid, by the crossing number); and sampled points inside the
/// polygon are in exactly one triangle, those outside in none.
void check_planar_triangulation(std::span<const Vec3> pts, const Embedding& at, const std::vector<TriangleIndices>& tris,
                                size_t expected, std::mt19937& rng) {
  const int n = static_cast<int>(pts.size());
  ASSERT_EQ(tris.size(), expected);
  std::vector<Vec2> poly;  // the corners in the plane's own coordinates, in units of `scale`
  for (const Vec3& p : pts) {
    const glm::dvec3 d = (glm::dvec3(p) - glm::dvec3(at.origin)) / static_cast<double>(at.scale);
    poly.emplace_back(static_cast<float>(glm::dot(d, glm::dvec3(at.e1))), static_cast<float>(glm::dot(d, glm::dvec3(at.e2))));
  }
  const glm::dvec3 up = glm::cross(glm::dvec3(at.e1), glm::dvec3(at.e2));
  const double whole = shoelace(poly);  // its sign is the polygon's winding
  const double unit = static_cast<double>(at.scale) * at.scale;
  double sum = 0.0;
  for (const TriangleIndices& t : tris) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_GE(t[k], 0);
      ASSERT_LT(t[k], n);
    }
    ASSERT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    const glm::dvec3 a(pts[t[0]]), b(pts[t[1]]), c(pts[t[2]]);
    const glm::dvec3 normal = glm::cross(b - a, c - a);
    EXPECT_GT(glm::dot(normal, up) * whole, 0.0) << "triangle not wound as the polygon";
    sum += std::fabs(glm::dot(normal, up));  // its area in the plane (the corners are off it by rounding)
    const Vec2 centroid = (poly[t[0]] + poly[t[1]] + poly[t[2]]) / 3.0f;
    EXPECT_TRUE(inside_polygon(poly, centroid)) << "triangle outside the polygon";
  }
  EXPECT_NEAR(sum / unit, std::fabs(whole), 1e-4 * std::fabs(whole));
  Vec2 lo = poly[0], hi = poly[0];
  for (Vec2 v : poly) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const float size = std::max(hi.x - lo.x, hi.y - lo.y);
  int inside = 0, outside = 0;
  for (int s = 0; s < 200; ++s) {
    const Vec2 p{test::uniform(rng, lo.x, hi.x), test::uniform(rng, lo.y, hi.y)};
    if (distance_to_outline(poly, p) < 1e-3 * size) continue;  // boundary: either answer
    int covering = 0;
    for (const TriangleIndices& t : tris) {
      const std::array<Vec2, 3> tri{poly[t[0]], poly[t[1]], poly[t[2]]};
      if (inside_polygon(tri, p)) ++covering;
    }
    const bool in = inside_polygon(poly, p);
    (in ? inside : outside) += 1;
    EXPECT_EQ(covering, in ? 1 : 0) << "point (" << p.x << ", " << p.y << ")";
  }
  EXPECT_GT(inside, 0);
}

/// The concave faces of RecastDemo's nav_test.obj kind: an 8-sided floor with a notch, and a
/// 12-sided cross-shaped floor.
const std::vector<Vec2> kNotched8{{0, 0}, {6, 0}, {6, 4}, {4, 4}, {4, 2}, {2, 2}, {2, 4}, {0, 4}};
const std::vector<Vec2> kCross12{{2, 0}, {4, 0}, {4, 2}, {6, 2}, {6, 4}, {4, 4},
                                 {4, 6}, {2, 6}, {2, 4}, {0, 4}, {0, 2}, {2, 2}};
/// A U of 12 vertices, 4 of them on straight stretches of its edges (T-junction candidates).
const std::vector<Vec2> kStraightU12{{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 1}, {3, 2},
                                     {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 1}};

TEST(PlanarPolygon, ConcaveNgonsInAnyPlaneBecomeNMinus2TrianglesThatTileThem) {
  std::mt19937 rng(15);
  const std::vector<std::vector<Vec2>> shapes{kLShape, kUShape, star(5, 3.0f, 1.0f), kNotched8, kCross12,
                                              kStraightU12, comb(4)};
  std::vector<Embedding> planes{Embedding{}};  // the xz floor
  planes.push_back({{0, 5, 0}, {0, 1, 0}, {0, 0, 1}});  // a wall (yz)
  for (int k = 0; k < 6; ++k) {  // random planes, some far from the origin, huge or tiny
    const Quat q = test::random_rotation(rng);
    Embedding at{test::random_point3(rng, 10.0f), q * Vec3(1, 0, 0), q * Vec3(0, 1, 0)};
    if (k == 1) at.origin += Vec3(1e4f, -2e4f, 3e4f);
    if (k == 2) at.scale = 1e37f, at.origin *= 1e36f;
    if (k == 3) at.scale = 1e-30f, at.origin *= 1e-30f;
    planes.push_back(at);
  }
  for (size_t i = 0; i < shapes.size(); ++i) {
    const std::vector<Vec2>& shape = shapes[i];
    for (size_t k = 0; k < planes.size(); ++k) {
      const Embedding& at = planes[k];
      for (const bool reverse : {false, true}) {
        SCOPED_TRACE("shape " + std::to_string(i) + ", plane " + std::to_string(k) + (reverse ? ", reversed" : ""));
        const std::vector<Vec2> poly = reverse ? reversed(shape) : shape;
        const std::vector<TriangleIndices> tris = triangulate_planar_polygon(placed(poly, at), "face");
        check_planar_triangulation(placed(poly, at), at, tris, poly.size() - 2, rng);
      }
    }
  }
}

TEST(PlanarPolygon, RandomStarShapedPolygonsInRandomPlanes) {
  std::mt19937 rng(1515);
  int triangulated = 0;
  for (int trial = 0; trial < 150; ++trial) {
    const int n = 3 + static_cast<int>(rng() % 60);
    std::vector<Vec2> poly = random_star_shaped(rng, n, 10.0f);
    if (trial % 2 == 1) poly = reversed(poly);
    const Quat q = test::random_rotation(rng);
    const Embedding at{test::random_point3(rng, 100.0f), q * Vec3(1, 0, 0), q * Vec3(0, 1, 0)};
    const std::vector<Vec3> pts = placed(poly, at);
    std::vector<TriangleIndices> tris;
    try {
      tris = triangulate_planar_polygon(pts, "random");
    } catch (const InvalidInput& e) {
      // Only near-duplicate angles can make a degenerate draw; they must say so.
      EXPECT_EQ(std::string(e.what()).rfind("random: polygon ", 0), 0u) << e.what();
      continue;
    }
    ++triangulated;
    check_planar_triangulation(pts, at, tris, static_cast<size_t>(n) - 2, rng);
  }
  EXPECT_GE(triangulated, 140);
}

// A round face of 1000 vertices turns by less at each corner than the outline rule calls
// straight (kDegenerateAreaTolerance of the size squared): TurnScale::triangle still finds ears.
TEST(PlanarPolygon, FineRoundFacesOfAThousandVerticesHaveEars) {
  std::mt19937 rng(1000);
  std::vector<Vec2> round, spiky = star(512, 10.0f, 6.0f);
  for (int i = 0; i < 1000; ++i) {
    const float a = 2.0f * test::kPi * static_cast<float>(i) / 1000.0f;
    round.push_back({10.0f * std::cos(a), 10.0f * std::sin(a)});
  }
  const Embedding tilted{{3, 4, 5}, {0.6f, 0.8f, 0}, {0, 0, 1}};
  for (const auto& poly : {round, spiky}) {
    check_planar_triangulation(placed(poly, tilted), tilted, triangulate_planar_polygon(placed(poly, tilted)),
                               poly.size() - 2, rng);
  }
  // The outline rule (decompose_convex's) finds none on the round outline's first corners.
  EXPECT_THROW((void)triangulate_ear_clipping(round), InvalidInput);
}

TEST(PlanarPolygon, VerticesOnStraightEdgesAreKeptAsCorners) {
  // Dropping one would leave a T-junction against the neighbouring face that uses it.
  std::mt19937 rng(3);
  const std::vector<TriangleIndices> tris = triangulate_planar_polygon(placed(kStraightU12, {}));
  check_planar_triangulation(placed(kStraightU12, {}), {}, tris, 10, rng);
  std::vector<int> used(kStraightU12.size(), 0);
  for (const TriangleIndices& t : tris)
    for (int c : t) used[static_cast<size_t>(c)] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 1), 12);
  // A 12-gon: a square with two extra vertices on each side (n - 2 triangles, every one used).
  std::vector<Vec2> square12;
  for (int side = 0; side < 4; ++side) {
    const Vec2 corners[4] = {{0, 0}, {3, 0}, {3, 3}, {0, 3}};
    const Vec2 a = corners[side], b = corners[(side + 1) % 4];
    for (int k = 0; k < 3; ++k) square12.push_back(a + (static_cast<float>(k) / 3.0f) * (b - a));
  }
  check_planar_triangulation(placed(square12, {}), {}, triangulate_planar_polygon(placed(square12, {})), 10, rng);
}

TEST(PlanarPolygon, RepeatedVerticesAreMergedWhileThreeRemain) {
  std::mt19937 rng(4);
  // The L with its third corner written twice, and with its first repeated at the end.
  std::vector<Vec2> twice = kLShape;
  twice.insert(twice.begin() + 2, kLShape[2]);
  const std::vector<TriangleIndices> tris = triangulate_planar_polygon(placed(twice, {}));
  check_planar_triangulation(placed(twice, {}), {}, tris, kLShape.size() - 2, rng);
  std::vector<Vec2> closed = kUShape;
  closed.push_back(kUShape[0]);
  check_planar_triangulation(placed(closed, {}), {}, triangulate_planar_polygon(placed(closed, {})), kUShape.size() - 2, rng);
}

TEST(PlanarPolygon, SlightlyBentFacesPassAndFoldedOnesAreRefused) {
  std::mt19937 rng(6);
  // A unit quad with one corner lifted by 1 % of its size: near-planar, two triangles.
  const std::vector<Vec3> bent{{0, 0, 0}, {1, 0, 0}, {1, 0.01f, 1}, {0, 0, 1}};
  const std::vector<TriangleIndices> tris = triangulate_planar_polygon(bent, "quad");
  ASSERT_EQ(tris.size(), 2u);
  double area = 0.0;
  for (const TriangleIndices& t : tris) {
    const Vec3 normal = cross(bent[t[1]] - bent[t[0]], bent[t[2]] - bent[t[0]]);
    EXPECT_LT(normal.y, 0.0f);  // wound as the quad: clockwise seen from +y
    area += 0.5 * static_cast<double>(length(normal));
  }
  EXPECT_NEAR(area, 1.0, 1e-3);
  // Lifted by 40 %: a corner 0.1 from the best-fit plane (two corners each side, 0.1 each).
  const std::vector<Vec3> twisted{{0, 0, 0}, {1, 0, 0}, {1, 0.4f, 1}, {0, 0, 1}};
  try {
    (void)triangulate_planar_polygon(twisted, "level.obj:7: face 2");
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()),
              "level.obj:7: face 2: polygon is not planar: vertex 2 lies 0.09623 from its best-fit plane, more than "
              "5% of its size 1 (kPlanarityTolerance)");
  }
  (void)rng;
}

TEST(PlanarPolygon, DegenerateAndSelfIntersectingFacesAreRefusedByName) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  auto message = [](const std::vector<Vec3>& pts) {
    try {
      (void)triangulate_planar_polygon(pts, "level.obj:9: face 4");
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto expect_has = [](const std::string& text, const char* part) {
    EXPECT_NE(text.find(part), std::string::npos) << text;
    EXPECT_EQ(text.rfind("level.obj:9: face 4: ", 0), 0u) << text;
  };
  expect_has(message({{0, 0, 0}, {1, nan, 0}, {1, 0, 1}, {0, 0, 1}}), "vertex 1: not finite");
  expect_has(message({{0, 0, 0}, {1, 0, 0}}), "at least 3");
  // Repeated vertices that leave fewer than 3: no area.
  expect_has(message({{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {1, 0, 0}}), "zero area");
  expect_has(message({{2, 1, 2}, {2, 1, 2}, {2, 1, 2}, {2, 1, 2}}), "zero area");
  expect_has(message({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {1, 1, 1}}), "zero area");
  // Bow-ties: symmetric (the two lobes' areas cancel: no Newell normal) and lopsided.
  EXPECT_EQ(message(placed(std::vector<Vec2>{{0, 0}, {2, 2}, {2, 0}, {0, 2}}, {})),
            "level.obj:9: face 4: polygon is self-intersecting: edge 0-1 meets edge 2-3");
  expect_has(message(placed(std::vector<Vec2>{{0, 0}, {4, 3}, {4, 0}, {0, 1}}, {})), "self-intersecting");
  // A 12-gon whose outline crosses itself, in a tilted plane.
  std::vector<Vec2> crossed = kCross12;
  std::swap(crossed[3], crossed[9]);
  expect_has(message(placed(crossed, {{1, 2, 3}, {0.6f, 0.8f, 0}, {0, 0, 1}})), "self-intersecting");
  // Touching itself at a vertex: a face through one vertex twice (two squares joined at a corner).
  expect_has(message(placed(std::vector<Vec2>{{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {1, 2}, {1, 1}, {0, 1}}, {})),
             "self-intersecting");
}

}  // namespace
}  // namespace collide
