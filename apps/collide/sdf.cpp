// `collide sdf FILE`: a map's, a scene's or a mesh's signed distance field, built and measured
// against exact distances; its picture, particles bounced off it, its values at given points.

#include "sdf.hpp"

#include "command_errors.hpp"
#include "run.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/field_picture.hpp>
#include <collide/io/obj.hpp>
#include <collide/io/points_text.hpp>
#include <collide/io/scene_json.hpp>
#include <collide/io/tiled.hpp>
#include <collide/narrow/closest_point.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <span>
#include <string_view>
#include <system_error>
#include <vector>

namespace collide::cli {
namespace {

/// K, M, G, T of --max-memory: powers of this.
constexpr double kBytesPerKilo = 1024.0;
/// Particles spawn where the field is at least this many voxels (in free space, not touching).
constexpr float kSpawnClearanceVoxels = 1.0f;
/// Spawning gives up after this many tries per particle (an input with little free space).
constexpr int kSpawnAttemptsPerParticle = 100;
/// The fastest particle moves this many voxels per step, the slowest kParticleMinSpeedFraction of
/// that: one step never carries a particle across more than a voxel (the field's resolution).
constexpr float kParticleMaxVoxelsPerStep = 1.0f;
constexpr float kParticleMinSpeedFraction = 0.25f;
/// A particle counts as inside at the end when the field there is below -this many voxels.
constexpr float kParticleInsideVoxels = 0.5f;
/// The winding number above which a point is inside a mesh (sdf/distance_field.hpp's rule).
constexpr float kInsideWindingNumber = 0.5f;
/// Significant digits of the values printed for --sample: a float read back is the same float.
constexpr int kSampleDigits = 9;
/// Seed stream of the particles (the check points use the seed alone).
constexpr std::uint32_t kParticleSeedStream = 2;
/// Bytes in a MiB, for the report.
constexpr double kMiB = 1024.0 * 1024.0;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// `x` as printf's %g writes it.
std::string g_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

/// `build()`, with the input file named in front of an error that does not name it already.
template <class Build>
auto naming_the_file(const std::string& in, Build&& build) -> decltype(build()) {
  try {
    return build();
  } catch (const InvalidInput& e) {
    if (std::string_view(e.what()).starts_with(in)) throw;
    throw InvalidInput(in + ": " + e.what());
  }
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// A plane of a 3D field to draw: the axis across it and where.
struct SliceSpec {
  int axis = 1;          ///< 0 x, 1 y, 2 z
  float value = 0.0f;    ///< world units along the axis
  bool given = false;    ///< false: y at the middle of the grid
};

/// --slice "AXIS=VALUE".
SliceSpec parse_slice(const std::string& text) {
  SliceSpec s;
  if (text.empty()) return s;
  const std::string bad = "--slice '" + text + "': expected AXIS=VALUE, AXIS x, y or z and VALUE a finite number "
                          "(world units), e.g. y=1.5";
  if (text.size() < 3 || text[1] != '=') throw InvalidInput(bad);
  const char axis = static_cast<char>(std::tolower(static_cast<unsigned char>(text[0])));
  if (axis < 'x' || axis > 'z') throw InvalidInput(bad);
  s.axis = axis - 'x';
  const char* first = text.data() + 2;
  const char* last = text.data() + text.size();
  if (*first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, s.value);
  if (ec != std::errc() || ptr != last || !std::isfinite(s.value)) throw InvalidInput(bad);
  s.given = true;
  return s;
}

/// The exact signed distance at a point, where it is known: 2D outside every shape (the nearest
/// shape's distance); 3D everywhere (the mesh's nearest triangle, signed by the winding number).
/// A 2D point inside a shape is inside the union, but its depth in the union is not the depth
/// in any one shape: `known` is false there.
struct ExactDistance {
  float distance = 0.0f;
  bool known = true;
};

ExactDistance exact_distance(const SdfInput& in, Vec2 p) {
  float nearest = std::numeric_limits<float>::infinity();
  for (const PlacedShape& s : in.shapes) {
    const PointQuery q = closest_point(s.shape, s.xf, p);
    if (q.inside) return {q.distance, false};
    nearest = std::min(nearest, q.distance);
  }
  return {nearest, true};
}

ExactDistance exact_distance(const SdfInput& in, Vec3 p) {
  const BvhNearest n = in.mesh.bvh.nearest(p - in.mesh.origin);  // the BVH holds mesh - origin
  const float d = std::sqrt(n.distance_squared);
  return {winding_number(in.mesh, p) > kInsideWindingNumber ? -d : d, true};
}

/// The field's error against exact distances on random points of its grid's box.
struct ErrorReport {
  int points = 0;
  int measured = 0;       ///< points whose exact distance is known
  double max_error = 0.0;
  double sum_error = 0.0;
  int right_sign = 0;     ///< points the field puts on the side the exact answer does
  int inside_only = 0;    ///< 2D points inside a shape: sign checked only
};

template <int D, class Field>
ErrorReport measure_error(const SdfInput& in, const Field& field, float clamp_to, int count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const AabbN<D> box = field.grid.bounds();
  ErrorReport r;
  r.points = count;
  for (int i = 0; i < count; ++i) {
    VecN<D> p;
    for (int k = 0; k < D; ++k) p[k] = std::uniform_real_distribution<float>(box.min[k], box.max[k])(rng);
    const float value = field.sample(p);
    const ExactDistance exact = exact_distance(in, p);
    if (!exact.known) {
      ++r.inside_only;
      r.right_sign += value < 0.0f ? 1 : 0;
      continue;
    }
    const float truth = std::clamp(exact.distance, -clamp_to, clamp_to);
    const double error = std::fabs(static_cast<double>(value) - static_cast<double>(truth));
    ++r.measured;
    r.max_error = std::max(r.max_error, error);
    r.sum_error += error;
    r.right_sign += (value < 0.0f) == (truth < 0.0f) ? 1 : 0;
  }
  return r;
}

/// The field's samples over a plane: the whole 2D grid, or a 3D grid's nodes across `slice`.
struct SliceSamples {
  std::vector<float> values;
  FieldSlice slice;
  FieldPictureOptions options;
  std::string where;  ///< ", slice y = 1.5" for 3D; empty for 2D
};

template <class Field>
  requires(Field::kDim == 2)
SliceSamples slice_samples(const Field& field, const SliceSpec&, bool y_down) {
  const auto& g = field.grid;
  SliceSamples s;
  s.values.reserve(g.count());
  for (int j = 0; j < g.dims.y; ++j) {
    for (int i = 0; i < g.dims.x; ++i) s.values.push_back(field.sample(g.node({i, j})));
  }
  s.slice = FieldSlice{s.values, g.dims.x, g.dims.y, g.voxel, g.origin};
  s.options.vertical_down = y_down;
  return s;
}

template <class Field>
  requires(Field::kDim == 3)
SliceSamples slice_samples(const Field& field, const SliceSpec& spec, bool) {
  const auto& g = field.grid;
  const Aabb3 box = g.bounds();
  const float value = spec.given ? spec.value : 0.5f * (box.min[spec.axis] + box.max[spec.axis]);
  const char* names = "xyz";
  if (!(value >= box.min[spec.axis] && value <= box.max[spec.axis])) {
    throw InvalidInput("--slice " + std::string(1, names[spec.axis]) + "=" + g_text(value) + ": outside the field's " +
                       names[spec.axis] + " range [" + g_text(box.min[spec.axis]) + ", " + g_text(box.max[spec.axis]) + "]");
  }
  // The plane's axes: across y, x right and z down (a y-up level seen from above); across x, z
  // right and y up; across z, x right and y up.
  const int u = spec.axis == 0 ? 2 : 0;
  const int v = spec.axis == 1 ? 2 : 1;
  SliceSamples s;
  s.values.reserve(static_cast<std::size_t>(g.dims[u]) * static_cast<std::size_t>(g.dims[v]));
  for (int j = 0; j < g.dims[v]; ++j) {
    for (int i = 0; i < g.dims[u]; ++i) {
      Vec3 p;
      p[spec.axis] = value;
      p[u] = g.origin[u] + static_cast<float>(i) * g.voxel;
      p[v] = g.origin[v] + static_cast<float>(j) * g.voxel;
      s.values.push_back(field.sample(p));
    }
  }
  s.slice = FieldSlice{s.values, g.dims[u], g.dims[v], g.voxel, {g.origin[u], g.origin[v]}};
  s.options.vertical_down = spec.axis == 1;
  s.options.horizontal_axis = std::string(1, names[u]);
  s.options.vertical_axis = std::string(1, names[v]);
  char where[64];
  std::snprintf(where, sizeof where, ", slice %c = %g", names[spec.axis], static_cast<double>(value));
  s.where = where;
  return s;
}

/// What the particles did.
struct ParticleReport {
  int placed = 0;
  double seconds = 0.0;       ///< in step_particles, summed over the frames
  std::size_t bounced = 0;    ///< summed over the frames
  std::size_t near = 0;
  int inside_at_end = 0;
};

template <int D, class Field>
ParticleReport bounce_particles(const SdfOptions& o, const SdfInput& in, const Field& field) {
  std::seed_seq seeds{o.seed, kParticleSeedStream};
  std::mt19937 rng(seeds);
  const float voxel = field.grid.voxel;
  const AabbN<D> box = field.grid.bounds();
  ParticlesN<D> particles;
  const float max_speed = kParticleMaxVoxelsPerStep * voxel / o.dt;
  std::uniform_real_distribution<float> speed(kParticleMinSpeedFraction * max_speed, max_speed);
  std::normal_distribution<float> gaussian;
  const long attempts = static_cast<long>(o.particles) * kSpawnAttemptsPerParticle;
  for (long a = 0; a < attempts && static_cast<int>(particles.positions.size()) < o.particles; ++a) {
    VecN<D> p;
    for (int k = 0; k < D; ++k) p[k] = std::uniform_real_distribution<float>(box.min[k], box.max[k])(rng);
    if (!(field.sample(p) >= kSpawnClearanceVoxels * voxel)) continue;
    VecN<D> dir;
    do {
      for (int k = 0; k < D; ++k) dir[k] = gaussian(rng);
    } while (glm::dot(dir, dir) == 0.0f);
    particles.positions.push_back(p);
    particles.velocities.push_back(speed(rng) * glm::normalize(dir));
  }
  VecN<D> gravity{0.0f};
  gravity[1] = in.y_down ? o.gravity : -o.gravity;  // "down" as the input shows it
  ParticleReport r;
  r.placed = static_cast<int>(particles.positions.size());
  for (int f = 0; f < o.frames && r.placed > 0; ++f) {
    if (o.gravity != 0.0f) {
      for (VecN<D>& v : particles.velocities) v += o.dt * gravity;
    }
    const Clock::time_point start = Clock::now();
    const ParticleStepStats s = step_particles(field, particles, o.dt, o.restitution);
    r.seconds += seconds_since(start);
    r.bounced += s.bounced;
    r.near += s.near;
  }
  for (const VecN<D>& p : particles.positions) r.inside_at_end += field.sample(p) < -kParticleInsideVoxels * voxel ? 1 : 0;
  return r;
}

template <int D>
std::string vector_text(VecN<D> v) {
  std::string out = "(";
  for (int k = 0; k < D; ++k) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%g", k > 0 ? ", " : "", static_cast<double>(v[k]));
    out += buf;
  }
  return out + ")";
}

template <int D>
std::string dims_text(glm::vec<D, int> dims) {
  std::string out;
  for (int k = 0; k < D; ++k) out += (k > 0 ? " x " : "") + std::to_string(dims[k]);
  return out;
}

/// The input's bounds' largest side.
float largest_side(const SdfInput& in) {
  if (in.dimension == 3) {
    const Aabb3 b = compute_aabb(in.mesh, Transform3{});
    return std::max({b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z});
  }
  Aabb box = compute_aabb(in.shapes[0].shape, in.shapes[0].xf);
  for (const PlacedShape& s : in.shapes) box = merge(box, compute_aabb(s.shape, s.xf));
  return std::max(box.max.x - box.min.x, box.max.y - box.min.y);
}

/// Everything after the build: the report, the picture, the particles, the samples.
template <int D, class Field>
int report_field(const SdfOptions& o, const SdfInput& in, const Field& field, double build_seconds,
                 const std::vector<VecN<D>>& samples, const SliceSpec& slice, std::FILE* report, std::FILE* values) {
  const auto& g = field.grid;
  const FieldBuildStats& st = field.stats;
  const float voxel = g.voxel;
  std::fprintf(report, "  grid              %s nodes, voxel %g, origin %s\n", dims_text<D>(g.dims).c_str(),
               static_cast<double>(voxel), vector_text<D>(g.origin).c_str());
  std::fprintf(report, "  build time        %.3f ms\n", 1e3 * build_seconds);
  std::fprintf(report, "  memory            %zu bytes (%.2f MiB)\n", field.bytes(), static_cast<double>(field.bytes()) / kMiB);
  std::fprintf(report, "  nodes             %zu\n", st.nodes);
  std::fprintf(report, "  band nodes        %zu (exact distances, within %g voxels of the surface)\n", st.band_nodes,
               static_cast<double>(o.band));
  std::fprintf(report, "  sign evaluations  %zu\n", st.sign_evaluations);
  if (st.nearest_queries > 0) {
    std::fprintf(report, "  nearest queries   %zu (the band through the mesh's BVH, a block of eight nodes a descent: a grid coarse beside its triangles)\n",
                 st.nearest_queries);
  }

  float clamp_to = std::numeric_limits<float>::infinity();
  if constexpr (requires { field.band_distance; }) clamp_to = field.band_distance;
  const ErrorReport e = measure_error<D>(in, field, clamp_to, o.check_points, o.seed);
  if (e.measured > 0) {
    const double mean = e.sum_error / e.measured;
    std::fprintf(report, "  error             max %.4g (%.3g voxels), mean %.4g (%.3g voxels) on %d random points of the grid's box (seed %u)\n",
                 e.max_error, e.max_error / voxel, mean, mean / voxel, e.measured, o.seed);
  } else {
    std::fprintf(report, "  error             no point to measure on (%d random points)\n", e.points);
  }
  if (D == 2) {
    std::fprintf(report, "                    exact: the nearest shape's distance, on the points outside every shape; "
                         "%d inside one: sign only\n", e.inside_only);
  } else {
    std::fprintf(report, "                    exact: the mesh's nearest triangle (BVH), inside where its winding number > %g\n",
                 static_cast<double>(kInsideWindingNumber));
  }
  if (o.sparse) {
    std::fprintf(report, "                    against the exact distance clamped to the band, +-%g\n",
                 static_cast<double>(clamp_to));
  }
  std::fprintf(report, "  sign              %d/%d points on the side the exact answer gives\n", e.right_sign, e.points);

  if (!o.png.empty()) {
    SliceSamples s = slice_samples(field, slice, in.y_down);
    s.options.title = std::filesystem::path(in.name).filename().string() + ": signed distance" + s.where + " (" +
                      (o.sparse ? "sparse" : "dense") + ", voxel " + g_text(voxel) + ")";
    s.options.size = o.png_size;
    s.options.unit = in.unit;
    const FieldPictureSize size = save_field_picture(s.slice, s.options, o.png);
    std::fprintf(report, "wrote %s (%d x %d)\n", o.png.c_str(), size.width, size.height);
  }

  if (o.particles > 0) {
    const ParticleReport p = bounce_particles<D>(o, in, field);
    const double steps = static_cast<double>(p.placed) * o.frames;
    std::fprintf(report, "particles: %d of %d placed in free space (seed %u), %d steps of %g s, restitution %g, gravity %g\n",
                 p.placed, o.particles, o.seed, o.frames, static_cast<double>(o.dt), static_cast<double>(o.restitution),
                 static_cast<double>(o.gravity));
    std::fprintf(report, "  step time         %.3g ns per particle step (%.3f ms in step_particles)\n",
                 steps > 0 ? 1e9 * p.seconds / steps : 0.0, 1e3 * p.seconds);
    std::fprintf(report, "  bounces           %zu (%zu particle steps near the surface: their cell read)\n", p.bounced, p.near);
    std::fprintf(report, "  ended inside      %d (the field below -%g voxels there at the end)\n", p.inside_at_end,
                 static_cast<double>(kParticleInsideVoxels));
  }

  // The --sample points as one batch (sample(field, points, out): the reads of several points
  // in flight together).
  std::vector<float> sampled(samples.size());
  sample(field, std::span<const VecN<D>>(samples), std::span<float>(sampled));
  for (const float value : sampled) std::fprintf(values, "%.*g\n", kSampleDigits, static_cast<double>(value));
  return 0;
}

template <int D>
int run_dimension(const SdfOptions& o, const SdfInput& in, std::FILE* report, std::FILE* values) {
  const SliceSpec slice = parse_slice(o.slice);
  std::vector<VecN<D>> samples;
  if (!o.sample.empty()) {
    require_input_file(o.sample);
    samples = io::load_points<D>(o.sample);
  }
  FieldOptions fo;
  const float side = largest_side(in);
  fo.voxel = o.voxel > 0.0f ? o.voxel : side / kSdfDefaultVoxelsPerSide;
  if (!(fo.voxel > 0.0f)) {
    throw InvalidInput(in.name + ": the input's bounds have no extent (largest side " + g_text(side) + "): give --voxel");
  }
  fo.margin = o.margin;
  fo.band = o.band;
  fo.max_bytes = o.max_bytes;
  // The report begins once the field is built: a refused build prints its error alone.
  const auto finish = [&](const auto& field, Clock::time_point start) {
    const double seconds = seconds_since(start);
    const std::string what = D == 2 ? std::to_string(in.shapes.size()) + " convex shapes"
                                    : std::to_string(in.mesh.triangle_count()) + " triangles";
    std::fprintf(report, "signed distance field of %s (%dD, %s):\n", in.name.c_str(), D, what.c_str());
    std::fprintf(report, "  kind              %s\n", o.sparse ? "sparse (narrow band)" : "dense");
    if (o.voxel <= 0.0f) {
      std::fprintf(report, "  voxel             %g (the default: largest side %g / %g)\n", static_cast<double>(fo.voxel),
                   static_cast<double>(side), static_cast<double>(kSdfDefaultVoxelsPerSide));
    }
    return report_field<D>(o, in, field, seconds, samples, slice, report, values);
  };
  const Clock::time_point start = Clock::now();
  if constexpr (D == 2) {
    const std::span<const PlacedShape> shapes(in.shapes);
    if (o.sparse) return finish(naming_the_file(in.name, [&] { return make_sparse_distance_field(shapes, fo); }), start);
    return finish(naming_the_file(in.name, [&] { return make_distance_field(shapes, fo); }), start);
  } else {
    if (o.sparse) return finish(naming_the_file(in.name, [&] { return make_sparse_distance_field(in.mesh, fo); }), start);
    return finish(naming_the_file(in.name, [&] { return make_distance_field(in.mesh, fo); }), start);
  }
}

}  // namespace

SdfInput load_sdf_input(const SdfOptions& o) {
  SdfInput in;
  in.name = o.input;
  const SceneFileKind kind = scene_file_kind(o.input);
  if (!o.layers.empty() && kind != SceneFileKind::tiled_map) {
    throw InvalidInput("--layers: only Tiled maps have layers, not '" + o.input + "'");
  }
  if (kind == SceneFileKind::tiled_map) {
    TiledLoadOptions load;
    load.layers = o.layers;
    const TiledMap map = naming_the_file(o.input, [&] { return load_tiled_map(o.input, load); });
    for (const TiledCollider& c : map.colliders) in.shapes.push_back({c.shape, c.transform});
    in.y_down = true;
    in.unit = "px";
    if (in.shapes.empty()) throw InvalidInput(o.input + ": no colliders on the map's colliding layers: no field to build");
  } else if (kind == SceneFileKind::scene_json) {
    const SceneDescription scene = naming_the_file(o.input, [&] { return load_scene_json(o.input); });
    for (const StaticDef& def : scene.statics) {
      if (def.sensor) continue;  // sensors push nothing: not part of the solid
      for (const Shape2D& shape : def.shapes) in.shapes.push_back({shape, def.transform});
    }
    if (in.shapes.empty()) throw InvalidInput(o.input + ": no solid statics (sensors are not solid): no field to build");
  } else if (lower(std::filesystem::path(o.input).extension().string()) == ".obj") {
    require_input_file(o.input);
    in.mesh = io::load_triangle_mesh(o.input);
    in.dimension = 3;
  } else {
    throw InvalidInput("'" + o.input + "': not a Tiled map (.tmx, .tmj, .json), a scene JSON file (.json) nor an OBJ mesh (.obj)");
  }
  return in;
}

std::size_t parse_byte_size(const std::string& text, const std::string& option) {
  const std::string bad = option + " '" + text + "': not a size (bytes, or a number followed by K, M, G or T: powers of 1024)";
  double number = 0.0;
  const char* last = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), last, number, std::chars_format::fixed);
  if (ec != std::errc() || ptr == text.data() || !(number > 0.0)) throw InvalidInput(bad);
  std::string suffix = lower(std::string(ptr, last));
  if (suffix.ends_with("ib")) suffix.resize(suffix.size() - 2);
  else if (suffix.size() == 2 && suffix.back() == 'b') suffix.pop_back();
  const std::string_view units = "kmgt";
  double scale = 1.0;
  if (suffix.size() == 1 && units.find(suffix[0]) != std::string_view::npos) {
    scale = std::pow(kBytesPerKilo, static_cast<double>(units.find(suffix[0]) + 1));
  } else if (!suffix.empty() && suffix != "b") {
    throw InvalidInput(bad);
  }
  const double bytes = std::floor(number * scale);
  if (!(bytes >= 1.0)) throw InvalidInput(bad);
  if (bytes >= static_cast<double>(std::numeric_limits<std::size_t>::max())) {
    throw InvalidInput(option + " '" + text + "': more bytes than a size holds");
  }
  return static_cast<std::size_t>(bytes);
}

int run_sdf(const SdfOptions& o, std::FILE* report, std::FILE* values) {
  if (!o.png.empty()) require_output_folder("--png", o.png);  // before the build, not after it
  (void)parse_slice(o.slice);                                  // the same
  const SdfInput in = load_sdf_input(o);
  if (!o.slice.empty() && in.dimension != 3) {
    throw InvalidInput("--slice: " + o.input + " is 2D: its whole field is drawn (a slice is for 3D, an OBJ mesh)");
  }
  return in.dimension == 2 ? run_dimension<2>(o, in, report, values) : run_dimension<3>(o, in, report, values);
}

}  // namespace collide::cli
