#include "run_common.hpp"

#include <collide/core/error.hpp>
#include <collide/world/world2d.hpp>
#include <collide/world/world3d.hpp>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cmath>

namespace collide::cli {

namespace {

/// The progress bar redraws at most this many times per run.
constexpr int kProgressUpdates = 100;
/// Width of the progress bar, characters.
constexpr int kProgressWidth = 40;

nlohmann::json collider_json(const ColliderRef& c, std::uint64_t user) {
  return {{c.is_static ? "static" : "body", c.index}, {"piece", c.piece}, {"user", user}};
}

template <int D>
nlohmann::json vec_json(const VecN<D>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (int k = 0; k < D; ++k) a.push_back(v[k]);
  return a;
}

template <int D>
nlohmann::json event_json(int frame, const ContactEventN<D>& e) {
  nlohmann::json points = nlohmann::json::array();
  for (int i = 0; i < e.manifold.count; ++i) {
    const ManifoldPointN<D>& p = e.manifold.points[static_cast<std::size_t>(i)];
    points.push_back({{"point", vec_json<D>(p.point)}, {"depth", p.depth}, {"id", p.id.key()}});
  }
  return {{"frame", frame},
          {"type", to_string(e.type)},
          {"a", collider_json(e.a, e.user_a)},
          {"b", collider_json(e.b, e.user_b)},
          {"sensor", e.sensor},
          {"normal", vec_json<D>(e.manifold.normal)},
          {"points", points},
          {"persisted", e.persisted_points}};
}

const char* check_name(int check) {
  static const char* const kNames[] = {"filter", "aabb", "exact"};
  return kNames[check];
}

}  // namespace

void check_run_steps(const RunOptions& o) {
  if (o.frames < 0) throw InvalidInput("--frames: negative");
  if (!std::isfinite(o.dt) || o.dt <= 0.0f) throw InvalidInput("--dt: must be positive and finite");
}

EventsFile::EventsFile(const RunOptions& o) : path_(o.events) {
  if (path_.empty()) return;
  file_.open(path_);
  if (!file_) throw InvalidInput("--events " + path_ + ": cannot be written");
}

template <int D>
void EventsFile::write(int frame, std::span<const ContactEventN<D>> events, std::int64_t& written) {
  if (!file_.is_open()) return;
  for (const ContactEventN<D>& e : events) {
    file_ << event_json<D>(frame, e).dump() << '\n';
    ++written;
  }
}

void EventsFile::finish() {
  if (!file_.is_open()) return;
  file_.flush();
  if (!file_) throw InvalidInput("--events " + path_ + ": write failed");
}

template void EventsFile::write<2>(int, std::span<const ContactEventN<2>>, std::int64_t&);
template void EventsFile::write<3>(int, std::span<const ContactEventN<3>>, std::int64_t&);

Progress::Progress(const RunOptions& o)
    : on_(o.progress && isatty(fileno(stderr)) != 0 && o.frames >= kProgressUpdates), frames_(o.frames) {}

void Progress::tick(int frame) {
  if (!on_ || frame % (frames_ / kProgressUpdates) != 0) return;
  const int filled = frame * kProgressWidth / frames_;
  std::fprintf(stderr, "\r[%.*s%*s] %3d%% frame %d/%d", filled, "########################################",
               kProgressWidth - filled, "", frame * 100 / frames_, frame, frames_);
  if (frame == frames_) std::fprintf(stderr, "\r%*s\r", kProgressWidth + 40, "");
  std::fflush(stderr);
}

template <int D>
void count_world(RunReport& r, const WorldN<D>& world) {
  r.bodies = world.body_count();
  r.statics = world.static_count();
  for (int i = 0; i < r.statics; ++i) {
    const auto pieces = static_cast<int>(world.static_def(StaticId{static_cast<std::uint32_t>(i)}).shapes.size());
    r.static_pieces += pieces;
    r.split_statics += pieces > 1 ? 1 : 0;
  }
}

template void count_world<2>(RunReport&, const WorldN<2>&);
template void count_world<3>(RunReport&, const WorldN<3>&);

double per_frame(std::int64_t total, int frames) {
  return frames > 0 ? static_cast<double>(total) / frames : 0.0;
}

double ms_per_frame(double seconds, int frames) { return frames > 0 ? 1e3 * seconds / frames : 0.0; }

void print_phases(std::FILE* out, const RunReport& r, bool sensors) {
  const StepStats& t = r.total;
  const int f = r.frames;
  std::fprintf(out, "per frame (mean)\n");
  std::fprintf(out, "  broad phase    %.1f body pairs, %.1f body-static candidates, %.1f checks skipped by speed bounds, %.2f rebuilds\n",
               per_frame(t.body_pairs, f), per_frame(t.static_candidates, f), per_frame(t.broad_skipped_checks, f),
               per_frame(t.broad_rebuilds, f));
  std::fprintf(out, "  early out      %.1f bodies clear of statics since an earlier frame, %.1f filtered, %.1f AABB rejected, %.1f pretest rejected\n",
               per_frame(t.static_clear_skips, f), per_frame(t.filtered, f), per_frame(t.aabb_rejected, f),
               per_frame(t.pretest_rejected, f));
  if (sensors) {
    std::fprintf(out, "  narrow phase   %.1f exact tests, %.1f contacts (%.1f with sensors), %.1f push-outs, %lld jammed in all\n",
                 per_frame(t.narrow_tests, f), per_frame(t.contacts, f), per_frame(t.sensor_contacts, f),
                 per_frame(t.pushes, f), static_cast<long long>(t.jammed));
  } else {
    std::fprintf(out, "  narrow phase   %.1f exact tests, %.1f contacts, %.1f push-outs, %lld jammed in all\n",
                 per_frame(t.narrow_tests, f), per_frame(t.contacts, f), per_frame(t.pushes, f),
                 static_cast<long long>(t.jammed));
  }
  std::fprintf(out,
               "  ccd            %.1f bodies moved by continuous collision (%.1f more fast ones clear of statics: no query), "
               "%.1f time of impact queries, %.1f hits\n",
               per_frame(t.ccd_bodies, f), per_frame(t.ccd_clear_skips, f), per_frame(t.toi_queries, f), per_frame(t.toi_hits, f));
  std::fprintf(out, "  events         %.1f begin, %.1f persist, %.1f end\n", per_frame(t.begin_events, f),
               per_frame(t.persist_events, f), per_frame(t.end_events, f));
}

void print_times(std::FILE* out, const RunReport& r, const std::string& extra) {
  const StepStats& t = r.total;
  const int f = r.frames;
  const double step_ms =
      ms_per_frame(t.time_integrate + t.time_statics + t.time_broad + t.time_bodies + t.time_events + t.time_check, f);
  std::fprintf(out, "time per frame (mean ms; %.3f total%s, %.1f s wall for the whole run)\n", step_ms, extra.c_str(),
               r.wall_seconds);
  std::fprintf(out, "  motion + ccd %.3f | statics %.3f | broad %.3f | body pairs %.3f | events %.3f | check %.3f\n",
               ms_per_frame(t.time_integrate, f), ms_per_frame(t.time_statics, f), ms_per_frame(t.time_broad, f),
               ms_per_frame(t.time_bodies, f), ms_per_frame(t.time_events, f), ms_per_frame(t.time_check, f));
}

template <int D>
void print_early_out(std::FILE* out, const WorldN<D>& world) {
  const auto reports = world.early_out_reports();
  const auto orders = world.early_out_orders();
  const auto pretests = world.early_out_pretests();
  const auto check_stats = world.early_out_check_stats();
  static const char* const kChains[] = {"body-static", "body-body"};
  std::fprintf(out, "early out (order by t / (1 - p); pretest while t_pre < (1 - p_pre) t_exact)\n");
  for (std::size_t c = 0; c < 2; ++c) {
    const CheckChainReport& rep = reports[c];
    std::fprintf(out, "  %-11s    %llu evaluations, %.1f%% rejected, %llu reorders; %s pretest %s\n", kChains[c],
                 static_cast<unsigned long long>(rep.evaluations),
                 rep.evaluations > 0 ? 100.0 * static_cast<double>(rep.rejections) / static_cast<double>(rep.evaluations)
                                     : 0.0,
                 static_cast<unsigned long long>(rep.reorders), D == 2 ? "circle" : "sphere",
                 pretests[c] ? "on" : "off");
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
}

template void print_early_out<2>(std::FILE*, const WorldN<2>&);
template void print_early_out<3>(std::FILE*, const WorldN<3>&);

void print_hash(std::FILE* out, const RunOptions& o, const RunReport& r) {
  if (!o.events.empty()) {
    std::fprintf(out, "  events         %lld written to %s\n", static_cast<long long>(r.events_written), o.events.c_str());
  }
  std::fprintf(out, "state hash       %016llx\n", static_cast<unsigned long long>(r.state_hash));
}

}  // namespace collide::cli
