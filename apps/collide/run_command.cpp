// `collide run [MAP|SCENE]`: the main job. Builds a scene (the embedded default scene, the
// bullets scene, a Tiled map with bodies spawned in its free space, or a scene JSON file), steps
// the world frame by frame with a turning laser, checks every frame independently (no body inside
// static geometry) and prints a per-phase summary and the final state hash.

#include "command_errors.hpp"
#include "commands.hpp"
#include "run.hpp"
#include "run_common.hpp"
#include "tbb_scheduler.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/cairo_picture.hpp>



#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

namespace collide::cli {
namespace {

/// Tiled maps: the layers used and skipped, each with what it held and why.
void print_layers(std::FILE* out, const RunOptions& o, const Scene& scene) {
  int used = 0, skipped = 0;
  for (const TiledLayer& l : scene.map_layers) {
    if (l.kind == TiledLayerKind::group) continue;
    (l.collides ? used : skipped) += 1;
  }
  if (used + skipped == 0) return;
  std::fprintf(out, "layers (%d used, %d skipped; %s)\n", used, skipped,
               o.layers.empty() ? "the map's declarations decide, or --layers NAME,..." : "chosen by --layers");
  for (const bool collides : {true, false}) {
    for (const TiledLayer& l : scene.map_layers) {
      if (l.kind == TiledLayerKind::group || l.collides != collides) continue;
      std::string held = to_string(l.kind);
      if (l.kind == TiledLayerKind::object) held += ", " + std::to_string(l.objects) + (l.objects == 1 ? " object" : " objects");
      if (l.kind == TiledLayerKind::tile) held += ", " + std::to_string(l.cells) + (l.cells == 1 ? " cell" : " cells");
      if (collides) held += ", " + std::to_string(l.colliders) + (l.colliders == 1 ? " collider" : " colliders");
      std::fprintf(out, "  %-8s '%s' (%s): %s\n", collides ? "used" : "skipped", l.name.c_str(), held.c_str(),
                   l.reason.c_str());
    }
  }
}

void print_summary(std::FILE* out, const RunOptions& o, const Scene& scene, const World2D& world,
                   const RunReport& r) {
  const StepStats& t = r.total;
  const int f = r.frames;
  std::fprintf(out, "collide run: %s\n", r.scene.c_str());
  std::fprintf(out, "  world          %d statics (%d convex pieces; %d of several: concave outlines, chains), %d bodies (%d bullets",
               r.statics, r.static_pieces, r.split_statics, r.bodies, scene.bullets);
  if (r.bodies < scene.requested_bodies) std::fprintf(out, "; %d asked, no free space for more", scene.requested_bodies);
  std::fprintf(out, ")\n");
  std::fprintf(out, "  spawn          %.3f s to build the scene and place its bodies\n", r.setup_seconds);
  std::fprintf(out, "  run            %d frames of %.2f ms, broad phase %s, early out %s, seed %u, %d thread%s\n", f,
               1e3 * static_cast<double>(o.dt), to_string(o.broad_phase),
               o.adaptive_early_out ? "adaptive" : "fixed order", scene.seed, r.threads, r.threads == 1 ? "" : "s");
  print_layers(out, o, scene);
  print_phases(out, r, /*sensors=*/true);
  if (scene.has_laser) {
    std::fprintf(out, "  laser          %.1f hits on statics (reflections and the last surface); last frame %d segments\n",
                 per_frame(r.laser_hits, f), r.laser_last_segments);
  } else {
    std::fprintf(out, "  laser          none in this scene\n");
  }
  print_times(out, r, "");
  print_early_out(out, world);
  std::fprintf(out, "check (independent, every frame)\n");
  std::fprintf(out, "  tunnelled      %lld bodies ended a frame inside static geometry (deepest overlap %.3g)\n",
               static_cast<long long>(t.tunnelled), static_cast<double>(t.max_static_depth));
  std::fprintf(out, "  escaped        %lld bodies ended a frame outside the world's bounds\n",
               static_cast<long long>(t.escaped));
  print_hash(out, o, r);
}

/// The close-up panel shows this many median body diameters across, so bodies stay large
/// enough to read on maps whose bodies are small against the level...
constexpr float kCloseUpBodies = 30.0f;
/// ...but at least the first and at most the second fraction of the world's width (bullets are
/// tiny, and their contacts are spread along walls).
constexpr float kCloseUpMinFraction = 1.0f / 12.0f;
constexpr float kCloseUpMaxFraction = 1.0f / 6.0f;
/// Widest aspect ratio of the close-up: a long, flat level still gets a close-up tall enough to
/// show a body standing on a platform.
constexpr float kCloseUpMaxAspect = 2.0f;
/// Contact normals in the close-up are arrows this fraction of its width long.
constexpr float kNormalArrowFraction = 0.045f;

/// The last frame: the whole world, and a close-up around the median contact (where things
/// happen), both with the laser. Roles are named in the picture's legend.
void write_pictures(const RunOptions& o, const Scene& scene, const World2D& world, const LaserPath& laser,
                    const RunReport& r) {
  PictureOptions po;
  po.width = o.picture_width;
  po.y_up = scene.y_up;
  po.title = "collide run: " + std::filesystem::path(scene.name).filename().string() + ", frame " + std::to_string(r.frames) + ", " +
             std::to_string(r.bodies) + " bodies, " + std::to_string(world.contacts().size()) +
             " contacts, tunnelled " + std::to_string(r.total.tunnelled);
  Picture picture(po);
  const Vec2 size = scene.bounds.max - scene.bounds.min;
  const Vec2 pad = 0.02f * size;
  picture.begin_panel("whole world", Aabb{scene.bounds.min - pad, scene.bounds.max + pad});
  world.draw(picture);  // normals a body's size long: dots at this scale, arrows in the close-up
  World2D::draw_laser(picture, laser);
  // Close-up: centred on the median contact (by x, then y), or the laser's first hit.
  std::vector<Vec2> spots;
  for (const Contact& c : world.contacts()) {
    if (c.manifold.count > 0) spots.push_back(c.manifold.points[0].point);
  }
  Vec2 center = laser.hit_count > 0 ? laser.hits[0].hit.point : scene.bounds.center();
  if (!spots.empty()) {
    auto mid = spots.begin() + static_cast<std::ptrdiff_t>(spots.size() / 2);
    std::nth_element(spots.begin(), mid, spots.end(),
                     [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    center = *mid;
  }
  std::vector<float> radii;  // half the larger side of each body's box
  for (const BodyId id : world.body_ids()) {
    const auto shapes = world.shapes(id);
    Aabb box = compute_aabb(shapes[0], world.transform(id));
    for (const Shape2D& s : shapes) box = merge(box, compute_aabb(s, world.transform(id)));
    radii.push_back(0.5f * std::max(box.max.x - box.min.x, box.max.y - box.min.y));
  }
  float width = kCloseUpMaxFraction * size.x;
  if (!radii.empty()) {
    std::nth_element(radii.begin(), radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2), radii.end());
    width = std::clamp(kCloseUpBodies * 2.0f * radii[radii.size() / 2], kCloseUpMinFraction * size.x, width);
  }
  const float aspect = std::min(size.x / size.y, kCloseUpMaxAspect);
  const Vec2 half = 0.5f * Vec2{width, width / aspect};
  picture.begin_panel("close-up", Aabb{center - half, center + half});
  world.draw(picture, WorldDrawOptions{.normal_length = kNormalArrowFraction * width});
  World2D::draw_laser(picture, laser);
  if (!o.svg.empty()) save_picture(picture, o.svg, PictureFormat::svg);
  if (!o.png.empty()) save_picture(picture, o.png, PictureFormat::png);
}

}  // namespace

RunReport run_world(const RunOptions& o, std::FILE* out) {
  if (is_3d_run(o)) return run_world3d(o, out);
  if (o.characters >= 0) throw InvalidInput("--characters: a 3D run's (an OBJ level, or --3d)");
  if (o.gravity != 0.0f) throw InvalidInput("--gravity: a 3D run's (an OBJ level, or --3d)");
  if (!o.view.empty()) throw InvalidInput("--view: a 3D run's (an OBJ level, or --3d)");
  check_run_steps(o);
  if (!o.png.empty()) require_output_folder("--png", o.png);  // before the run, not after it
  if (!o.svg.empty()) require_output_folder("--svg", o.svg);
  const auto setup = std::chrono::steady_clock::now();
  Scene scene = make_scene(o);
  World2D& world = scene.world;
  RunReport r;
  r.setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - setup).count();
  r.threads = scene.scheduler->worker_count();
  EventsFile events(o);
  r.scene = scene.name;
  count_world(r, world);
  r.frames = o.frames;
  Progress progress(o);
  LaserPath laser;
  const auto start = std::chrono::steady_clock::now();
  for (int frame = 1; frame <= o.frames; ++frame) {
    world.step(o.dt);
    if (scene.has_laser) {
      const float angle = scene.laser_turn * static_cast<float>(frame);
      const Ray ray{scene.laser.origin,
                    rotate(Rot2::from_angle(std::sin(angle) * kLaserSweepRadians), scene.laser.translation)};
      laser = world.cast_laser(ray, kMaxLaserBounces, QueryFilter{.bodies = false});  // statics are the mirrors
      r.laser_hits += laser.hit_count;
    }
    events.write<2>(frame, world.events(), r.events_written);
    progress.tick(frame);
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  events.finish();
  r.total = world.total_stats();
  r.laser_last_segments = laser.segments;
  r.state_hash = world.state_hash();
  if (!o.png.empty() || !o.svg.empty()) write_pictures(o, scene, world, laser, r);
  if (out != nullptr) {
    print_summary(out, o, scene, world, r);
    if (!o.svg.empty()) std::fprintf(out, "wrote %s\n", o.svg.c_str());
    if (!o.png.empty()) std::fprintf(out, "wrote %s\n", o.png.c_str());
  }
  return r;
}

void register_run_command(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  auto broad = std::make_shared<std::string>("temporal");
  auto fixed_order = std::make_shared<bool>(false);
  auto quiet = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand(
      "run", "Run a collision world: the embedded default scene, the bullets scene, a Tiled map, a scene JSON file, "
             "an OBJ level (3D) or the embedded 3D scene (--3d)");
  cmd->add_option("SCENE", o->input,
                  "Tiled map (.tmx, .tmj, .json), scene JSON file (.json, see docs/scene-json.md), OBJ level (.obj, 3D, "
                  "y up) or embedded scene (default, bullets); default: default");
  cmd->add_option("--bodies", o->bodies,
                  "Bodies to spawn (default scene 3000, bullets 500, maps 300, scene files their spawn count)")
      ->check(CLI::Range(0, kMaxRunBodies));
  cmd->add_option("--threads", o->threads, "Worker threads of the step (oneTBB); 0: every core")
      ->capture_default_str()
      ->check(CLI::Range(0, kMaxThreads));
  cmd->add_option("--density", o->density,
                  "Default scene: bodies per area relative to its own (3000 per 320 x 180 tile; in 3D, 500 per "
                  "40 x 12 x 40 room); the scene grows with --bodies at this density")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 1000.0));
  CLI::Option* seed = cmd->add_option("--seed", o->seed, "Random seed of the scene (overrides a scene file's)")
                          ->capture_default_str();
  cmd->add_option("--frames", o->frames, "Frames to run")->capture_default_str()->check(CLI::Range(0, 100000000));
  cmd->add_option("--dt", o->dt, "Seconds per frame")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--broadphase", *broad,
                  "Body broad phase: temporal, hierarchical_grid, sorted_grid, loose_grid, hash_grid, dynamic_tree, "
                  "sweep_and_prune, brute_force")
      ->capture_default_str();
  cmd->add_flag("--fixed-order", *fixed_order, "Keep the early-out checks in declaration order (no learning)");
  cmd->add_option("--events", o->events, "Write contact events (begin, persist, end) as JSON Lines");
  cmd->add_option("--png", o->png, "Write a picture of the last frame (PNG)");
  cmd->add_option("--svg", o->svg, "Write a picture of the last frame (SVG)");
  cmd->add_option("--width", o->picture_width, "Picture width, pixels")->capture_default_str()->check(CLI::Range(kMinPictureWidth, kMaxPictureSide));
  cmd->add_option("--layers", o->layers,
                  "Tiled maps: the tile and object layers that collide, by name (a group's name takes its layers), "
                  "comma-separated; default: the layers the map declares (a layer class collision/solid, a property "
                  "collides=true, a name containing \"collision\"), else every layer")
      ->delimiter(',')
      ->allow_extra_args(false);  // --layers a,b MAP: MAP is the scene, not a third layer
  cmd->add_flag("--no-progress", *quiet, "No progress bar (it is drawn only when stderr is a terminal)");
  cmd->add_flag("--3d", o->three_d, "Run the embedded 3D scene (a SCENE ending in .obj is a 3D level)");
  cmd->add_option("--characters", o->characters,
                  "3D: characters walking the floors with move_character (default 8)")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--gravity", o->gravity, "3D: the bodies' gravity along -y, world units per second squared (default 0)")
      ->check(CLI::Range(-1e6, 1e6));
  cmd->add_option("--view", o->view,
                  "3D: the camera of --png: AZIMUTH,ELEVATION[,ZOOM] in degrees (azimuth about +y from +z, "
                  "elevation above the floor, zoom > 1 closer) or iso, top, front, side (default iso)");
  cmd->callback([o, broad, fixed_order, quiet, seed]() {
    const int code = run_guarded("run", o->input.empty() ? "default" : o->input, [&] {
      o->seed_given = seed->count() > 0;
      o->broad_phase = world_broad_phase_from_string(*broad);
      o->adaptive_early_out = !*fixed_order;
      o->progress = !*quiet;
      const RunReport r = run_world(*o, stdout);
      if (r.total.tunnelled != 0 || r.total.escaped != 0 || r.characters_inside != 0) {
        std::fprintf(stderr, "collide run: the independent check failed (%lld tunnelled, %lld escaped, %lld character moves inside)\n",
                     static_cast<long long>(r.total.tunnelled), static_cast<long long>(r.total.escaped),
                     static_cast<long long>(r.characters_inside));
        return 3;
      }
      return 0;
    });
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace collide::cli
