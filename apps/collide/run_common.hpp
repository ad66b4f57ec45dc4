#pragma once
// What the 2D run (run_command.cpp) and the 3D run (run3d.cpp) share: the checks of the steps'
// options, the events file, the progress bar, the report's world counts and the summary's
// dimension-free blocks (per-phase numbers, times, the early-out chains, the state hash).

#include "run.hpp"

#include <collide/world/world.hpp>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <span>
#include <string>

namespace collide::cli {

/// Throws InvalidInput naming --frames or --dt when they cannot run.
void check_run_steps(const RunOptions& o);

/// --events: each step's contact events as JSON Lines (frame, type, colliders with user ids,
/// sensor, normal, points with depths and feature ids, persisted points); nothing when the option
/// is not given.
class EventsFile {
 public:
  /// Opens the file; throws InvalidInput naming --events and the path when it cannot be written.
  explicit EventsFile(const RunOptions& o);
  /// Writes the events of `frame`, counting them in `written`.
  template <int D>
  void write(int frame, std::span<const ContactEventN<D>> events, std::int64_t& written);
  /// Flushes; throws InvalidInput naming the path when a write failed.
  void finish();

 private:
  std::string path_;
  std::ofstream file_;
};

/// The progress bar on stderr: drawn when the run asks for it, stderr is a terminal and the run
/// has at least kProgressUpdates frames; redrawn that many times at most, wiped at the end.
class Progress {
 public:
  explicit Progress(const RunOptions& o);
  void tick(int frame);

 private:
  bool on_ = false;
  int frames_ = 0;
};

/// Counts of a run's world: bodies, statics, pieces, statics of several pieces.
template <int D>
void count_world(RunReport& r, const WorldN<D>& world);

/// total / frames, 0 for no frames; seconds as milliseconds per frame.
[[nodiscard]] double per_frame(std::int64_t total, int frames);
[[nodiscard]] double ms_per_frame(double seconds, int frames);

/// The summary's "per frame (mean)" block; `sensors`: the narrow phase line names the contacts
/// with sensors too. The laser's line comes from the caller.
void print_phases(std::FILE* out, const RunReport& r, bool sensors);
/// The summary's "time per frame" block; `extra`: more said in its first line's parentheses.
void print_times(std::FILE* out, const RunReport& r, const std::string& extra);
/// What the early-out chains learned: each check's cost t and pass rate p, the order, and what
/// it saved against the declaration order (by the model, and measured on sampled pairs).
template <int D>
void print_early_out(std::FILE* out, const WorldN<D>& world);
/// The summary's last lines: the events written (when asked) and the state hash.
void print_hash(std::FILE* out, const RunOptions& o, const RunReport& r);

}  // namespace collide::cli
