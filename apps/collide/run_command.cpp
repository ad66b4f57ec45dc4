// `collide run [MAP|SCENE]`: the main job. Builds a scene (the embedded default scene, the
// bullets scene, a Tiled map with bodies spawned in its free space, or a scene JSON file), steps
// the world frame by frame with a turning laser, checks every frame independently (no body inside
// static geometry) and prints a per-phase summary and the final state hash.

#include "command_errors.hpp"
#include "commands.hpp"
#include "run.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/cairo_picture.hpp>

#include <nlohmann/json.hpp>

#include <unistd.h>

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

/// The progress bar redraws at most this many times per run.
constexpr int kProgressUpdates = 100;
/// Width of the progress bar, characters.
constexpr int kProgressWidth = 40;

nlohmann::json collider_json(const ColliderRef& c, std::uint64_t user) {
  return {{c.is_static ? "static" : "body", c.index}, {"piece", c.piece}, {"user", user}};
}

nlohmann::json event_json(int frame, const ContactEvent& e) {
  nlohmann::json points = nlohmann::json::array();
  for (int i = 0; i < e.manifold.count; ++i) {
    const ManifoldPoint& p = e.manifold.points[static_cast<std::size_t>(i)];
    points.push_back({{"point", {p.point.x, p.point.y}}, {"depth", p.depth}, {"id", p.id.key()}});
  }
  return {{"frame", frame},
          {"type", to_string(e.type)},
          {"a", collider_json(e.a, e.user_a)},
          {"b", collider_json(e.b, e.user_b)},
          {"sensor", e.sensor},
          {"normal", {e.manifold.normal.x, e.manifold.normal.y}},
          {"points", points},
          {"persisted", e.persisted_points}};
}

void draw_progress(int frame, int frames) {
  const int filled = frames > 0 ? frame * kProgressWidth / frames : kProgressWidth;
  std::fprintf(stderr, "\r[%.*s%*s] %3d%% frame %d/%d", filled,
               "########################################", kProgressWidth - filled, "",
               frames > 0 ? frame * 100 / frames : 100, frame, frames);
  if (frame == frames) std::fprintf(stderr, "\r%*s\r", kProgressWidth + 40, "");
  std::fflush(stderr);
}

double per_frame(std::int64_t total, int frames) {
  return frames > 0 ? static_cast<double>(total) / frames : 0.0;
}

double ms_per_frame(double seconds, int frames) { return frames > 0 ? 1e3 * seconds / frames : 0.0; }

const char* check_name(int check) {
  static const char* const kNames[] = {"filter", "aabb", "exact"};
  return kNames[check];
}

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
  std::fprintf(out, "  run            %d frames of %.2f ms, broad phase %s, early out %s, seed %u\n", f,
               1e3 * static_cast<double>(o.dt), to_string(o.broad_phase),
               o.adaptive_early_out ? "adaptive" : "fixed order", scene.seed);
  print_layers(out, o, scene);
  std::fprintf(out, "per frame (mean)\n");
  std::fprintf(out, "  broad phase    %.1f body pairs, %.1f body-static candidates, %.1f checks skipped by speed bounds\n",
               per_frame(t.body_pairs, f), per_frame(t.static_candidates, f), per_frame(t.broad_skipped_checks, f));
  std::fprintf(out, "  early out      %.1f filtered, %.1f AABB rejected, %.1f pretest rejected\n",
               per_frame(t.filtered, f), per_frame(t.aabb_rejected, f), per_frame(t.pretest_rejected, f));
  std::fprintf(out, "  narrow phase   %.1f exact tests, %.1f contacts (%.1f with sensors), %.1f push-outs\n",
               per_frame(t.narrow_tests, f), per_frame(t.contacts, f), per_frame(t.sensor_contacts, f),
               per_frame(t.pushes, f));
  std::fprintf(out, "  ccd            %.1f bodies moved by continuous collision, %.1f time of impact queries, %.1f hits\n",
               per_frame(t.ccd_bodies, f), per_frame(t.toi_queries, f), per_frame(t.toi_hits, f));
  std::fprintf(out, "  events         %.1f begin, %.1f persist, %.1f end\n", per_frame(t.begin_events, f),
               per_frame(t.persist_events, f), per_frame(t.end_events, f));
  if (scene.has_laser) {
    std::fprintf(out, "  laser          %.1f hits on statics (reflections and the last surface); last frame %d segments\n",
                 per_frame(r.laser_hits, f), r.laser_last_segments);
  } else {
    std::fprintf(out, "  laser          none in this scene\n");
  }
  const double step_ms = ms_per_frame(t.time_integrate + t.time_statics + t.time_broad + t.time_bodies +
                                          t.time_events + t.time_check,
                                      f);
  std::fprintf(out, "time per frame (mean ms; %.3f total, %.1f s wall for the whole run)\n", step_ms, r.wall_seconds);
  std::fprintf(out, "  motion + ccd %.3f | statics %.3f | broad %.3f | body pairs %.3f | events %.3f | check %.3f\n",
               ms_per_frame(t.time_integrate, f), ms_per_frame(t.time_statics, f), ms_per_frame(t.time_broad, f),
               ms_per_frame(t.time_bodies, f), ms_per_frame(t.time_events, f), ms_per_frame(t.time_check, f));
  const auto reports = world.early_out_reports();
  const auto orders = world.early_out_orders();
  const auto pretests = world.early_out_pretests();
  const auto check_stats = world.early_out_check_stats();
  static const char* const kChains[] = {"body-static", "body-body"};
  std::fprintf(out, "early out (order by t / (1 - p); pretest while t_pre < (1 - p_pre) t_exact)\n");
  for (std::size_t c = 0; c < 2; ++c) {
    const CheckChainReport& rep = reports[c];
    std::fprintf(out, "  %-11s    %llu evaluations, %.1f%% rejected, %llu reorders; circle pretest %s\n", kChains[c],
                 static_cast<unsigned long long>(rep.evaluations),
                 rep.evaluations > 0 ? 100.0 * static_cast<double>(rep.rejections) / static_cast<double>(rep.evaluations)
                                     : 0.0,
                 static_cast<unsigned long long>(rep.reorders), pretests[c] ? "on" : "off");
    std::fprintf(out, "                 order:");
    for (std::size_t k = 0; k < 3; ++k) {
      const int check = orders[c][k];
      const CheckStats& cs = check_stats[c][static_cast<std::size_t>(check)];
      std::fprintf(out, "%s %s (t %.1f ns, p %.2f)", k == 0 ? "" : ",", check_name(check), cs.cost, cs.pass_rate);
    }
    std::fprintf(out, "\n");
    std::fprintf(out, "                 saved: model %.1f vs fixed order %.1f ns per pair (%.0f%%)", rep.expected_cost,
                 rep.fixed_order_cost, 100.0 * rep.saved_fraction());
    if (rep.sampled_pairs > 0) {
      std::fprintf(out, "; measured on %llu sampled pairs %.1f vs %.1f ns (%.0f%%)",
                   static_cast<unsigned long long>(rep.sampled_pairs), rep.sampled_cost, rep.sampled_fixed_order_cost,
                   100.0 * rep.sampled_saved_fraction());
    }
    std::fprintf(out, "\n");
  }
  std::fprintf(out, "check (independent, every frame)\n");
  std::fprintf(out, "  tunnelled      %lld bodies ended a frame inside static geometry (deepest overlap %.3g)\n",
               static_cast<long long>(t.tunnelled), static_cast<double>(t.max_static_depth));
  std::fprintf(out, "  escaped        %lld bodies ended a frame outside the world's bounds\n",
               static_cast<long long>(t.escaped));
  if (!o.events.empty()) {
    std::fprintf(out, "  events         %lld written to %s\n", static_cast<long long>(r.events_written), o.events.c_str());
  }
  std::fprintf(out, "state hash       %016llx\n", static_cast<unsigned long long>(r.state_hash));
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
  if (o.frames < 0) throw InvalidInput("--frames: negative");
  if (!std::isfinite(o.dt) || o.dt <= 0.0f) throw InvalidInput("--dt: must be positive and finite");
  if (!o.png.empty()) require_output_folder("--png", o.png);  // before the run, not after it
  if (!o.svg.empty()) require_output_folder("--svg", o.svg);
  Scene scene = make_scene(o);
  World2D& world = scene.world;
  std::ofstream events;
  if (!o.events.empty()) {
    events.open(o.events);
    if (!events) throw InvalidInput("--events " + o.events + ": cannot be written");
  }
  RunReport r;
  r.scene = scene.name;
  r.bodies = world.body_count();
  r.statics = world.static_count();
  for (int i = 0; i < r.statics; ++i) {
    const auto pieces = static_cast<int>(world.static_def(StaticId{static_cast<std::uint32_t>(i)}).shapes.size());
    r.static_pieces += pieces;
    r.split_statics += pieces > 1 ? 1 : 0;
  }
  r.frames = o.frames;
  const bool progress = o.progress && isatty(fileno(stderr)) != 0 && o.frames >= kProgressUpdates;
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
    if (events.is_open()) {
      for (const ContactEvent& e : world.events()) {
        events << event_json(frame, e).dump() << '\n';
        ++r.events_written;
      }
    }
    if (progress && frame % (o.frames / kProgressUpdates) == 0) draw_progress(frame, o.frames);
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (events.is_open()) {
    events.flush();
    if (!events) throw InvalidInput("--events " + o.events + ": write failed");
  }
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
      ->check(CLI::Range(0, 1000000));
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
