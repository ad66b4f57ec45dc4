// `collide walk MESH.obj`: builds the walk mesh of a level for an agent, wanders agents over it,
// checks every position independently, and optionally draws the mesh and the paths from above.

#include "command_errors.hpp"
#include "commands.hpp"

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/draw/cairo_picture.hpp>
#include <collide/io/obj.hpp>
#include <collide/walkmesh/make_walk_mesh.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace collide::cli {
namespace {

struct WalkOptions {
  std::string mesh;
  float max_slope_degrees = 45.0f;
  float agent_height = 2.0f;
  int agents = 16;
  int steps = 500;
  float speed = 0.1f;    ///< step length per tick, world units
  float wander = 0.3f;   ///< largest heading change per tick, radians
  unsigned seed = 1;
  std::string png;
  int png_size = 1024;
};

// The top-down picture (--png): the walk mesh by island on a dark ground, walls (boundary edges)
// dark, each agent's path in its own colour from a white dot to a dot of its colour.
constexpr Color kGround{32, 32, 40, 255};
constexpr Color kWall{20, 20, 20, 255};
constexpr Color kPathStart{255, 255, 255, 255};
/// Margin around the mesh, a fraction of the picture's side.
constexpr float kPictureMargin = 0.03f;
/// Widths and sizes, pixels.
constexpr float kWallWidth = 1.5f;
constexpr float kPathWidth = 2.0f;
constexpr float kPathEndRadius = 4.0f;

/// A random walk point, uniform over the mesh's area.
WalkPoint random_walk_point(const WalkMesh& mesh, const std::vector<float>& cumulative_area, std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float x = unit(rng) * cumulative_area.back();
  const auto t = static_cast<std::uint32_t>(std::min<std::size_t>(
      std::upper_bound(cumulative_area.begin(), cumulative_area.end(), x) - cumulative_area.begin(),
      cumulative_area.size() - 1));
  float u = unit(rng), v = unit(rng);
  if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
  return mesh.walk_point(t, {1.0f - u - v, u, v});
}

/// Two unit vectors spanning the ground plane (perpendicular to up), for steering and the picture.
void ground_basis(Vec3 up, Vec3& right, Vec3& forward) {
  const Vec3 any = std::fabs(up.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 0, 1);
  right = glm::normalize(any - glm::dot(any, up) * up);
  forward = glm::cross(right, up);
}

Color island_color(std::uint32_t island) {
  const std::uint32_t h = island * 2654435761u;
  return {static_cast<std::uint8_t>(150 + (h >> 8) % 90), static_cast<std::uint8_t>(150 + (h >> 16) % 90),
          static_cast<std::uint8_t>(150 + (h >> 24) % 90), 255};
}

int run_walk(const WalkOptions& o) {
  const Vec3 up{0.0f, 1.0f, 0.0f};
  if (!o.png.empty()) require_output_folder("--png", o.png);  // before the walk, not after it
  require_input_file(o.mesh);
  const TriangleSoup level = io::load_obj(o.mesh);
  const WalkAgent agent{o.max_slope_degrees * std::numbers::pi_v<float> / 180.0f, o.agent_height, up};
  const WalkMesh mesh = make_walk_mesh(level, agent);
  const WalkMeshStats& s = mesh.stats();
  std::printf("walk mesh of %s (max slope %.1f deg, agent height %.2f):\n", level.name.c_str(),
              static_cast<double>(o.max_slope_degrees), static_cast<double>(o.agent_height));
  std::printf("  level triangles   %zu\n", s.input_triangles);
  std::printf("  degenerate        %zu\n", s.degenerate_triangles);
  std::printf("  too steep         %zu\n", s.too_steep_triangles);
  std::printf("  no headroom       %zu (%zu partly kept)\n", s.low_headroom_triangles, s.headroom_refined_triangles);
  std::printf("  triangles kept    %zu (%zu duplicates dropped, %zu T-junction splits)\n", s.triangles,
              s.duplicate_triangles, s.t_junction_splits);
  std::printf("  vertices          %zu (%zu welded)\n", s.vertices, s.welded_vertices);
  std::printf("  islands           %zu\n", s.islands);
  std::printf("  boundary edges    %zu\n", s.boundary_edges);
  std::printf("  non-manifold      %zu edges; %zu triangles re-wound, %zu winding conflicts cut\n",
              s.non_manifold_edges, s.flipped_triangles, s.orientation_conflicts);

  std::vector<float> cumulative(mesh.triangle_count());
  float area = 0.0f;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) cumulative[t] = (area += mesh.triangle_area(t));
  Vec3 right, forward;
  ground_basis(up, right, forward);

  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<float> turn(-o.wander, o.wander);
  std::uniform_real_distribution<float> any_angle(-std::numbers::pi_v<float>, std::numbers::pi_v<float>);
  struct Agent {
    WalkPoint at;
    float heading;
    Vec3 last;               ///< the position before this step (for the check)
    std::vector<Vec3> path;  ///< every position, kept only for the picture
  };
  const bool keep_paths = !o.png.empty();  // else memory would grow with agents x steps
  std::vector<Agent> agents(static_cast<std::size_t>(o.agents));
  for (Agent& a : agents) {
    a.at = random_walk_point(mesh, cumulative, rng);
    a.heading = any_angle(rng);
    a.last = mesh.to_world_point(a.at);
    if (keep_paths) a.path.push_back(a.last);
  }
  // The independent check, by code other than the walking code: each position must be a valid
  // point of its triangle (is_valid), lie on the mesh as nearest_walk_point (the BVH) sees it, and
  // be no further from the last position than the step is long (no jump to another place or
  // floor). Float precision of positions: kRelativeTolerance of the coordinates' magnitude.
  const float on_mesh_tolerance = kRelativeTolerance * (mesh.size() + glm::length(mesh.origin()));
  double distance = 0.0, worst = 0.0, worst_move = 0.0;
  long crossings = 0, wall_hits = 0, blocked = 0, off_mesh = 0, checks = 0;
  for (int step = 0; step < o.steps; ++step) {
    for (Agent& a : agents) {
      a.heading += turn(rng);
      const Vec3 dir = std::cos(a.heading) * right + std::sin(a.heading) * forward;
      const WalkResult r = mesh.walk(a.at, o.speed * dir);
      distance += r.distance;
      crossings += r.edges_crossed;
      wall_hits += r.walls_hit;
      if (r.status != WalkStatus::completed) {
        ++blocked;
        a.heading = any_angle(rng);  // wander off somewhere else
      } else if (r.walls_hit > 0) {
        // Slid along a wall: go on along it rather than pressing into it for the next steps.
        const Vec2 along{glm::dot(r.end_step, right), glm::dot(r.end_step, forward)};
        if (glm::dot(along, along) > 0.0f) a.heading = std::atan2(along.y, along.x);
      }
      a.at = r.end;
      const Vec3 p = mesh.to_world_point(a.at);
      const double gap = glm::length(mesh.to_world_point(mesh.nearest_walk_point(p)) - p);
      const double move = glm::length(p - a.last);
      worst = std::max(worst, gap);
      worst_move = std::max(worst_move, move);
      ++checks;
      if (!mesh.is_valid(a.at) || gap > on_mesh_tolerance || move > o.speed + on_mesh_tolerance) ++off_mesh;
      a.last = p;
      if (keep_paths) a.path.push_back(p);
    }
  }
  std::printf("walked %d agents x %d steps of %.3f (seed %u):\n", o.agents, o.steps, static_cast<double>(o.speed), o.seed);
  std::printf("  distance walked   %.2f\n", distance);
  std::printf("  edges crossed     %ld\n", crossings);
  std::printf("  wall hits         %ld (slid along or stopped)\n", wall_hits);
  std::printf("  stopped at walls  %ld\n", blocked);
  std::printf("  on-mesh check     %ld/%ld positions on the mesh (largest gap %.3g, tolerance %.3g; "
              "largest move %.3g for steps of %.3g)\n",
              checks - off_mesh, checks, worst, static_cast<double>(on_mesh_tolerance), worst_move,
              static_cast<double>(o.speed));

  if (!o.png.empty()) {
    // Top-down picture: ground coordinates (right, forward) fitted into the square.
    const Aabb3 b = mesh.bounds();
    Vec2 lo{std::numeric_limits<float>::max()}, hi{-std::numeric_limits<float>::max()};
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
      const Vec3 p = mesh.world_vertex(v) - b.min;
      const Vec2 g{glm::dot(p, right), glm::dot(p, forward)};
      lo = glm::min(lo, g);
      hi = glm::max(hi, g);
    }
    const float margin = kPictureMargin * static_cast<float>(o.png_size);
    const float scale = (static_cast<float>(o.png_size) - 2.0f * margin) / std::max(hi.x - lo.x, hi.y - lo.y);
    auto to_pixel = [&](Vec3 world) {
      const Vec3 p = world - b.min;
      return Vec2{margin + scale * (glm::dot(p, right) - lo.x), margin + scale * (hi.y - glm::dot(p, forward))};
    };
    // Lower triangles first so upper floors cover them.
    std::vector<std::uint32_t> order(mesh.triangle_count());
    for (std::uint32_t t = 0; t < order.size(); ++t) order[t] = t;
    auto height = [&](std::uint32_t t) { return glm::dot(mesh.to_world_point(mesh.walk_point(t, Vec3(1.0f))), up); };
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return height(x) < height(y); });
    auto line_to = [](cairo_t* cr, Vec2 p) { cairo_line_to(cr, p.x, p.y); };
    save_drawing(o.png, PictureFormat::png, o.png_size, o.png_size, [&](cairo_t* cr) {
      set_source(cr, kGround);
      cairo_paint(cr);
      cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
      cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
      for (std::uint32_t t : order) {
        const glm::uvec3 tri = mesh.triangle(t);
        // Triangles are filled without anti-aliasing: two neighbours each blended over the ground
        // on their own would leave a faint seam along their shared edge. The walls, stroked with
        // anti-aliasing, smooth the outline.
        cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
        cairo_new_path(cr);
        for (int k = 0; k < 3; ++k) line_to(cr, to_pixel(mesh.world_vertex(tri[k])));
        cairo_close_path(cr);
        set_source(cr, island_color(mesh.island(t)));
        cairo_fill(cr);
        cairo_set_antialias(cr, CAIRO_ANTIALIAS_DEFAULT);
        for (int e = 0; e < 3; ++e) {
          if (mesh.neighbor(t, e) != kNoNeighbor) continue;
          const Vec2 from = to_pixel(mesh.world_vertex(tri[e]));
          cairo_move_to(cr, from.x, from.y);
          line_to(cr, to_pixel(mesh.world_vertex(tri[(e + 1) % 3])));
        }
        cairo_set_line_width(cr, kWallWidth);
        set_source(cr, kWall);
        cairo_stroke(cr);
      }
      for (std::size_t i = 0; i < agents.size(); ++i) {
        const std::uint32_t h = static_cast<std::uint32_t>(i + 1) * 2246822519u;
        const Color ink{static_cast<std::uint8_t>(200 + (h >> 8) % 56), static_cast<std::uint8_t>((h >> 16) % 160),
                        static_cast<std::uint8_t>((h >> 24) % 200), 220};
        const auto& path = agents[i].path;
        cairo_new_path(cr);
        for (const Vec3& p : path) line_to(cr, to_pixel(p));
        cairo_set_line_width(cr, kPathWidth);
        set_source(cr, ink);
        cairo_stroke(cr);
        for (const auto& [at, color] : {std::pair{path.front(), kPathStart}, std::pair{path.back(), ink}}) {
          const Vec2 c = to_pixel(at);
          cairo_new_sub_path(cr);
          cairo_arc(cr, c.x, c.y, kPathEndRadius, 0.0, 2.0 * std::numbers::pi);  // Cairo takes doubles
          set_source(cr, color);
          cairo_fill(cr);
        }
      }
    });
    std::printf("wrote %s (%d x %d, top-down: walk mesh by island, walls dark, paths from white dots)\n",
                o.png.c_str(), o.png_size, o.png_size);
  }
  return off_mesh == 0 ? 0 : 3;
}

}  // namespace

void register_walk_command(CLI::App& app) {
  auto options = std::make_shared<WalkOptions>();
  CLI::App* cmd = app.add_subcommand("walk", "Build the walk mesh of an OBJ level and wander agents over it");
  cmd->add_option("MESH", options->mesh, "Level mesh (.obj), y up")->required();
  cmd->add_option("--max-slope", options->max_slope_degrees, "Steepest walkable slope, degrees")
      ->capture_default_str()->check(CLI::Range(0.0f, 89.9f));
  cmd->add_option("--agent-height", options->agent_height, "Free height the agent needs above the ground")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--agents", options->agents, "Number of agents")->capture_default_str()->check(CLI::Range(1, 100000));
  cmd->add_option("--steps", options->steps, "Steps per agent")->capture_default_str()->check(CLI::Range(0, 10000000));
  cmd->add_option("--speed", options->speed, "Length of one step, world units")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--wander", options->wander, "Largest heading change per step, radians")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--seed", options->seed, "Random seed")->capture_default_str();
  cmd->add_option("--png", options->png, "Write a top-down picture of the walk mesh and the paths");
  cmd->add_option("--png-size", options->png_size, "Picture side, pixels")->capture_default_str()->check(CLI::Range(16, kMaxPictureSide));
  cmd->callback([options]() {
    const int code = run_guarded("walk", options->mesh, [&] { return run_walk(*options); });
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace collide::cli
