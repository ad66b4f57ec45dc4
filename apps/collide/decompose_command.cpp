// `collide decompose MESH.obj`: approximate convex decomposition of a triangle mesh
// (decompose/approximate_decomposition.hpp): the hulls written as an OBJ (one object per hull),
// the run's report printed (what the split saw, what was measured on both surfaces, the time),
// and optionally a picture of the input beside its hulls, each hull in its own colour. With
// --hulls, another tool's hulls of the mesh are read instead, measured and drawn the same way.

#include "command_errors.hpp"
#include "commands.hpp"
#include "tbb_scheduler.hpp"

#include <collide/core/error.hpp>
#include <collide/decompose/approximate_decomposition.hpp>
#include <collide/draw/palette.hpp>
#include <collide/draw/picture.hpp>
#include <collide/draw/view3d.hpp>
#include <collide/io/obj.hpp>
#include <collide/shape/draw_shape.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>

#include <unistd.h>

namespace collide::cli {
namespace {

/// The camera of --png: the `collide run --view iso` angles (degrees), both panels alike.
constexpr float kPictureAzimuthDegrees = 35.0f;
constexpr float kPictureElevationDegrees = 30.0f;

struct DecomposeOptions {
  std::string mesh;
  std::string out;  ///< hulls OBJ; empty: not written
  std::string hulls;  ///< --hulls: a decomposition to measure and draw instead of making one
  std::string png;  ///< picture; empty: none
  int png_width = 1400;
  int threads = 0;  ///< 0: every core
  bool progress = true;
  ApproximateDecompositionOptions decomposition;  ///< its scheduler is set by run_decompose
};

/// `x` as a percentage of `whole` (0 when whole is 0).
double percent(float x, float whole) {
  return whole > 0.0f ? 100.0 * static_cast<double>(x) / static_cast<double>(whole) : 0.0;
}

/// The picture (--png): the input mesh on the left, its hulls on the right, each hull its own
/// colour (distinct_color in the order made), seen from the same camera, nothing cut away.
void write_picture(const DecomposeOptions& o, const TriangleMesh& mesh, std::span<const ConvexHull> hulls_drawn,
                   const std::string& title) {
  Picture3D picture;
  picture.set_role_name(DrawRole::static_geometry, "input mesh");
  picture.set_role_name(DrawRole::body, "hulls (a colour each)");
  draw_shape(picture, mesh, Transform3{}, DrawRole::static_geometry);
  Aabb3 box = compute_aabb(mesh, Transform3{});
  for (std::size_t h = 0; h < hulls_drawn.size(); ++h) {
    const ConvexHull& hull = hulls_drawn[h];
    const Color color = distinct_color(static_cast<int>(h));
    for (const HullFace& f : hull.faces) {
      const Vec3 a = hull.vertices[hull.face_vertices[f.first]];
      for (int k = 1; k + 1 < f.count; ++k) {
        picture.draw_triangle(a, hull.vertices[hull.face_vertices[f.first + k]],
                              hull.vertices[hull.face_vertices[f.first + k + 1]], DrawRole::body, color);
      }
    }
    box.min = glm::min(box.min, hull.bounds.min);
    box.max = glm::max(box.max, hull.bounds.max);
  }
  constexpr float kDegree = std::numbers::pi_v<float> / 180.0f;
  const Camera3 camera = camera_framing(box, kPictureAzimuthDegrees * kDegree, kPictureElevationDegrees * kDegree);
  View3DPanel input{camera, "input: " + std::to_string(mesh.triangle_count()) + " triangles"};
  input.roles = {DrawRole::static_geometry};
  View3DPanel hulls{camera, std::to_string(hulls_drawn.size()) + " convex hull" + (hulls_drawn.size() == 1 ? "" : "s")};
  hulls.roles = {DrawRole::body};
  // Nothing is cut away: a prop is seen from outside, whichever way its triangles are wound.
  picture.write_png(o.png, {input, hulls}, View3DOptions{.width = o.png_width, .title = title, .cutaway = false});
}

/// The measured half of the report (measure_decomposition's figures).
void print_error(const DecompositionError& e, float diag, std::uint64_t seed) {
  std::printf("  hull_to_mesh    %.4g (%.3g%% of the diagonal): how far the hulls reach outside the mesh\n",
              static_cast<double>(e.hull_to_mesh), percent(e.hull_to_mesh, diag));
  std::printf("  mesh_to_hull    %.4g (%.3g%% of the diagonal): how far the mesh reaches outside the hulls\n",
              static_cast<double>(e.mesh_to_hull), percent(e.mesh_to_hull, diag));
  std::printf("  volume ratio    %.4g (the hulls' volumes over the mesh's)\n", static_cast<double>(e.volume_ratio));
  std::printf("  samples         %d on the hulls, %d on the mesh (seed %llu)\n", e.hull_samples, e.mesh_samples,
              static_cast<unsigned long long>(seed));
}

/// `--hulls FILE`: another decomposition of the mesh (V-HACD's, CoACD's, an artist's) read
/// (io::load_hulls_obj), measured by the same yardstick as collide's own, and drawn.
int run_measure_hulls(const DecomposeOptions& o, const TriangleMesh& mesh, const std::string& name) {
  if (o.decomposition.measure_samples < 1) throw InvalidInput("--samples: at least 1 with --hulls (it measures them)");
  require_input_file(o.hulls);
  const std::vector<ConvexHull> hulls = io::load_hulls_obj(o.hulls);
  const DecompositionError e = measure_decomposition(mesh, hulls, o.decomposition.measure_samples, o.decomposition.seed);
  const Aabb3 box = compute_aabb(mesh, Transform3{});
  const float diag = glm::length(box.max - box.min);
  std::size_t hull_vertices = 0;
  for (const ConvexHull& h : hulls) hull_vertices += h.vertices.size();
  const std::string hulls_name = std::filesystem::path(o.hulls).filename().string();
  std::printf("collide decompose: %s measured against %s\n", hulls_name.c_str(), name.c_str());
  std::printf("  input           %u triangles, %zu vertices, diagonal %.4g\n", mesh.triangle_count(), mesh.vertices.size(),
              static_cast<double>(diag));
  std::printf("  hulls           %zu\n", hulls.size());
  std::printf("  hull vertices   %zu\n", hull_vertices);
  print_error(e, diag, o.decomposition.seed);
  if (!o.out.empty()) {
    io::write_hulls_obj(o.out, hulls);
    std::printf("wrote %s (%zu hulls, one OBJ object each)\n", o.out.c_str(), hulls.size());
  }
  if (!o.png.empty()) {
    write_picture(o, mesh, hulls, "collide decompose: " + name + ", the hulls of " + hulls_name);
    std::printf("wrote %s (the input mesh and the hulls, a colour each)\n", o.png.c_str());
  }
  return 0;
}

int run_decompose(DecomposeOptions& o) {
  // CLI11's range check lets NaN through (every comparison with it is false).
  if (!(o.decomposition.concavity >= 0.0f && o.decomposition.concavity <= 1.0f)) {
    throw InvalidInput("--concavity: " + std::to_string(o.decomposition.concavity) + " is not a number in [0, 1]");
  }
  if (!o.out.empty()) require_output_folder("--out", o.out);  // before the work, not after it
  if (!o.png.empty()) require_output_folder("--png", o.png);
  require_input_file(o.mesh);
  const TriangleMesh mesh = io::load_triangle_mesh(o.mesh);
  const std::string name = std::filesystem::path(o.mesh).filename().string();
  if (!o.hulls.empty()) return run_measure_hulls(o, mesh, name);
  const std::shared_ptr<TaskScheduler> scheduler = make_scheduler(o.threads);
  o.decomposition.scheduler = scheduler.get();

  // A progress line on a terminal, rewritten after each split.
  const bool show_progress = o.progress && isatty(fileno(stderr)) != 0;
  auto report_progress = [&](int hulls, float worst) {
    std::fprintf(stderr, "\rcollide decompose: %d hull%s, worst concavity %.4g   ", hulls, hulls == 1 ? "" : "s",
                 static_cast<double>(worst));
    std::fflush(stderr);
  };
  std::optional<DecompositionProgress> progress;
  if (show_progress) progress.emplace(report_progress);
  ApproximateDecomposition d;
  try {
    d = decompose_approximate(mesh, o.decomposition, progress);
  } catch (const InvalidInput& e) {
    if (show_progress) std::fputs("\n", stderr);
    throw InvalidInput(name + ": " + e.what());  // what the decomposition refused, in this file
  }
  if (show_progress) std::fputs("\n", stderr);

  std::size_t hull_vertices = 0;
  for (const ConvexHull& h : d.hulls) hull_vertices += h.vertices.size();
  const auto diag = d.diagonal;
  const double target = static_cast<double>(o.decomposition.concavity) * static_cast<double>(diag);
  std::printf("collide decompose: %s\n", name.c_str());
  std::printf("  input           %u triangles, %zu vertices (%zu degenerate triangles dropped), diagonal %.4g\n",
              mesh.triangle_count(), mesh.vertices.size(), mesh.stats.degenerate_triangles, static_cast<double>(diag));
  std::printf("  voxel           %.4g (%.3g%% of the diagonal)\n", static_cast<double>(d.voxel), percent(d.voxel, diag));
  std::printf("  grid nodes      %d\n", d.grid_nodes);
  std::printf("  solid nodes     %d\n", d.solid_nodes);
  std::printf("  hulls           %zu (at most %d asked)\n", d.hulls.size(), o.decomposition.max_hulls);
  std::printf("  hull vertices   %zu (at most %d per hull)\n", hull_vertices, o.decomposition.max_vertices);
  std::printf("  splits          %d\n", d.splits);
  std::printf("  candidates      %d planes evaluated\n", d.candidates);
  std::printf("  grid concavity  %.4g (%.3g%% of the diagonal; target %.4g, %.3g%%)\n",
              static_cast<double>(d.grid_concavity), percent(d.grid_concavity, diag), target,
              100.0 * static_cast<double>(o.decomposition.concavity));
  if (d.error) {
    print_error(*d.error, diag, o.decomposition.seed);
  } else {
    std::printf("  measured        not measured (--samples 0)\n");
  }
  std::printf("  time            %.3f s (field %.3f s, measure %.3f s)\n", d.seconds, d.field_seconds, d.measure_seconds);
  std::printf("  threads         %d\n", scheduler->worker_count());

  if (!o.out.empty()) {
    io::write_hulls_obj(o.out, d.hulls);
    std::printf("wrote %s (%zu hulls, one OBJ object each)\n", o.out.c_str(), d.hulls.size());
  }
  if (!o.png.empty()) {
    char title[256];
    std::snprintf(title, sizeof title, "collide decompose: %s, at most %d hulls of %d vertices, concavity %g of the diagonal",
                  name.c_str(), o.decomposition.max_hulls, o.decomposition.max_vertices,
                  static_cast<double>(o.decomposition.concavity));
    write_picture(o, mesh, d.hulls, title);
    std::printf("wrote %s (the input mesh and its hulls, a colour each)\n", o.png.c_str());
  }
  return 0;
}

}  // namespace

void register_decompose_command(CLI::App& app) {
  auto o = std::make_shared<DecomposeOptions>();
  auto quiet = std::make_shared<bool>(false);
  ApproximateDecompositionOptions& d = o->decomposition;
  CLI::App* cmd = app.add_subcommand(
      "decompose", "Split a concave triangle mesh into convex hulls (approximate convex decomposition)");
  cmd->add_option("MESH", o->mesh,
                  "Triangle mesh (.obj): closed or nearly closed (holes and self-touching parts are taken as the "
                  "solid they bound)")
      ->required();
  cmd->add_option("--out", o->out, "Write the hulls as an OBJ file, one object (o hull_N) per hull, in MESH's coordinates");
  cmd->add_option("--max-hulls", d.max_hulls, "Most hulls")
      ->capture_default_str()->check(CLI::Range(1, kDecompositionMaxHulls));
  cmd->add_option("--concavity", d.concavity,
                  "Split until every hull reaches at most this far outside the mesh, a fraction of its bounding "
                  "box's diagonal (0: spend the whole --max-hulls budget)")
      ->capture_default_str()->check(CLI::Range(0.0f, 1.0f));
  cmd->add_option("--max-vertices", d.max_vertices, "Most vertices per hull")
      ->capture_default_str()->check(CLI::Range(4, kMaxHullVertices));
  cmd->add_option("--resolution", d.resolution,
                  "Grid nodes over the mesh's bounding box: more splits finer and concavity is measured finer, slower")
      ->capture_default_str()->check(CLI::Range(kDecompositionMinResolution, kDecompositionMaxResolution));
  cmd->add_option("--seed", d.seed, "Random seed of the measurement's surface samples")->capture_default_str();
  cmd->add_option("--samples", d.measure_samples,
                  "Surface samples of the measurement, on the mesh and as many over the hulls (0: not measured)")
      ->capture_default_str()->check(CLI::Range(0, kDecompositionMaxSamples));
  cmd->add_option("--threads", o->threads, "Worker threads (oneTBB); 0: every core. The hulls are the same for any")
      ->capture_default_str()->check(CLI::Range(0, kMaxThreads));
  cmd->add_option("--hulls", o->hulls,
                  "Measure and draw this OBJ of convex hulls (another tool's decomposition of MESH: one connected "
                  "surface per hull) instead of decomposing MESH; --out, --png, --samples and --seed apply");
  cmd->add_option("--png", o->png, "Write a shaded picture: the input mesh beside its hulls, each hull in its own colour");
  cmd->add_option("--width", o->png_width, "Picture width, pixels")
      ->capture_default_str()->check(CLI::Range(kMinPictureWidth, kMaxViewSide));
  cmd->add_flag("--no-progress", *quiet, "No progress line (it is drawn only when stderr is a terminal)");
  cmd->footer(
      "Prints the input, the grid, the hulls, the search (splits, candidate planes), the concavity the split saw, "
      "the distances measured by sampling both surfaces (hull_to_mesh: how far the hulls reach outside the mesh; "
      "mesh_to_hull: what they miss), the hulls' volume over the mesh's, the time and the threads.\n"
      "Examples:\n"
      "  collide decompose ../shared/data/meshes/fcl/rob.obj --out rob_hulls.obj --png rob_hulls.png\n"
      "  collide decompose chair.obj --max-hulls 32 --concavity 0.005 --out chair_hulls.obj");
  cmd->callback([o, quiet]() {
    const int code = run_guarded("decompose", o->mesh, [&] {
      o->progress = !*quiet;
      return run_decompose(*o);
    });
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace collide::cli
