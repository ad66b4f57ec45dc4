#include <collide/broad/temporal_broad_phase.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace collide {

namespace {

/// A sleeping pair wakes this fraction of its gap-closing time early: rounding in the wake
/// time can never make it late.
constexpr double kWakeEarly = 1e-6;

/// Growth of a box over the horizon is capped here, far inside float range (a huge speed bound
/// then just makes that object a candidate with everything).
constexpr double kMaxGrowth = 1e30;

}  // namespace

template <int D>
TemporalBroadPhaseN<D>::TemporalBroadPhaseN(Options options) : options_(options) {
  if (!std::isfinite(options.horizon) || options.horizon < 0.0) {
    throw InvalidInput("TemporalBroadPhase options horizon: negative or not finite");
  }
}

template <int D>
void TemporalBroadPhaseN<D>::build(std::span<const AabbN<D>> boxes,
                                   std::span<const float> speed_bounds, double time) {
  validate_boxes(boxes);
  if (speed_bounds.size() != boxes.size()) {
    throw InvalidInput("speed bounds: " + std::to_string(speed_bounds.size()) + " for " +
                       std::to_string(boxes.size()) + " boxes");
  }
  for (std::size_t i = 0; i < speed_bounds.size(); ++i) {
    if (!std::isfinite(speed_bounds[i]) || speed_bounds[i] < 0.0f) {
      throw InvalidInput("speed bound " + std::to_string(i) + ": negative or not finite");
    }
  }
  if (!std::isfinite(time)) throw InvalidInput("time: not finite");
  boxes_.assign(boxes.begin(), boxes.end());
  speeds_.assign(speed_bounds.begin(), speed_bounds.end());
  time_ = time;
  stats_ = Stats{};
  needs_rebuild_ = true;

  horizon_ = options_.horizon;
  if (horizon_ == 0.0) {
    // Half the median box size over the median positive speed bound.
    scratch_.clear();
    for (const float v : speeds_) {
      if (v > 0.0f) scratch_.push_back(v);
    }
    if (scratch_.empty()) {
      horizon_ = std::numeric_limits<double>::infinity();
    } else {
      auto mid = scratch_.begin() + static_cast<std::ptrdiff_t>(scratch_.size() / 2);
      std::nth_element(scratch_.begin(), mid, scratch_.end());
      const double speed = *mid;
      const double cell = suggest_cell_size(boxes, scratch_);  // twice the median size
      horizon_ = 0.25 * cell / speed;
    }
  }
}

template <int D>
void TemporalBroadPhaseN<D>::update(std::span<const AabbN<D>> boxes, double time) {
  validate_boxes(boxes);
  if (boxes.size() != boxes_.size()) {
    throw InvalidInput("boxes: " + std::to_string(boxes.size()) + " given, " +
                       std::to_string(boxes_.size()) + " built; call build for a new set");
  }
  if (!std::isfinite(time) || time < time_) throw InvalidInput("time: not finite or goes back");
  const double dt = time - time_;
  const int n = size();
  for (int i = 0; i < n; ++i) {
    const AabbN<D>& before = boxes_[i];
    const AabbN<D>& now = boxes[i];
    const double reach = static_cast<double>(speeds_[i]) * dt;
    bool within = true;
    for (int k = 0; k < D; ++k) {
      within = within &&
               static_cast<double>(before.min[k]) - static_cast<double>(now.min[k]) <= reach &&
               static_cast<double>(now.max[k]) - static_cast<double>(before.max[k]) <= reach;
    }
    if (!within) {
      ++stats_.bound_violations;
      needs_rebuild_ = true;
    } else if (!needs_rebuild_ && !contains(grown_[i], now)) {
      needs_rebuild_ = true;  // left its grown box: the candidate set no longer covers it
    }
  }
  boxes_.assign(boxes.begin(), boxes.end());
  time_ = time;
}

template <int D>
void TemporalBroadPhaseN<D>::set_speed_bounds(std::span<const float> speed_bounds) {
  if (speed_bounds.size() != speeds_.size()) {
    throw InvalidInput("speed bounds: " + std::to_string(speed_bounds.size()) + " for " +
                       std::to_string(speeds_.size()) + " objects");
  }
  for (std::size_t i = 0; i < speed_bounds.size(); ++i) {
    if (!std::isfinite(speed_bounds[i]) || speed_bounds[i] < 0.0f) {
      throw InvalidInput("speed bound " + std::to_string(i) + ": negative or not finite");
    }
  }
  bool any_raised = false;
  raised_.assign(speeds_.size(), 0);
  for (std::size_t i = 0; i < speeds_.size(); ++i) {
    if (speed_bounds[i] > speeds_[i]) {
      raised_[i] = 1;
      any_raised = true;
    }
    speeds_[i] = speed_bounds[i];
  }
  if (!any_raised || needs_rebuild_) return;
  // A sleeping pair with a faster object may meet sooner than its wake time: check it at the
  // next find_pairs. (Its grown box assumed the old bound, too; update() rebuilds when an
  // object leaves it.)
  for (std::size_t c = 0; c < candidates_.size(); ++c) {
    if (raised_[std::size_t(candidates_[c].first)] || raised_[std::size_t(candidates_[c].second)]) {
      wake_[c] = std::min(wake_[c], time_);
    }
  }
}

template <int D>
void TemporalBroadPhaseN<D>::rebuild() {
  grown_.resize(boxes_.size());
  for (std::size_t i = 0; i < boxes_.size(); ++i) {
    // The horizon is infinite only when every speed bound is 0.
    const double margin = speeds_[i] > 0.0f ? speeds_[i] * horizon_ : 0.0;
    grown_[i] = fatten(boxes_[i], static_cast<float>(std::min(margin, kMaxGrowth)));
  }
  grid_.build(grown_);
  grid_.find_pairs(candidates_);
  wake_.assign(candidates_.size(), time_);
  built_at_ = time_;
  needs_rebuild_ = false;
  ++stats_.rebuilds;
  stats_.candidate_pairs = static_cast<std::int64_t>(candidates_.size());
}

template <int D>
void TemporalBroadPhaseN<D>::find_pairs(PairList& pairs) {
  pairs.clear();
  if (needs_rebuild_ || time_ > built_at_ + horizon_) rebuild();
  const std::size_t count = candidates_.size();
  for (std::size_t c = 0; c < count; ++c) {
    if (wake_[c] > time_) {
      ++stats_.skipped_checks;
      continue;
    }
    ++stats_.checks;
    const auto [a, b] = candidates_[c];
    const AabbN<D>& box_a = boxes_[a];
    const AabbN<D>& box_b = boxes_[b];
    if (overlap(box_a, box_b)) {
      pairs.emplace_back(a, b);
      wake_[c] = time_;
      continue;
    }
    double gap = 0.0;
    for (int k = 0; k < D; ++k) {
      gap = std::max({gap, static_cast<double>(box_b.min[k]) - box_a.max[k],
                      static_cast<double>(box_a.min[k]) - box_b.max[k]});
    }
    const double closing = static_cast<double>(speeds_[a]) + speeds_[b];
    wake_[c] = closing > 0.0 ? time_ + (gap / closing) * (1.0 - kWakeEarly)
                             : std::numeric_limits<double>::infinity();
  }
}

template <int D>
void TemporalBroadPhaseN<D>::query(const AabbN<D>& box, QueryCallback callback) const {
  if (!grid_is_current()) {
    for (int i = 0; i < size(); ++i) {
      if (overlap(box, boxes_[i]) && !callback(i)) return;
    }
    return;
  }
  grid_.query(box, [&](int id) { return !overlap(box, boxes_[id]) || callback(id); });
}

template <int D>
void TemporalBroadPhaseN<D>::query_point(const VecN<D>& point, QueryCallback callback) const {
  if (!grid_is_current()) {
    for (int i = 0; i < size(); ++i) {
      if (contains(boxes_[i], point) && !callback(i)) return;
    }
    return;
  }
  grid_.query_point(point, [&](int id) { return !contains(boxes_[id], point) || callback(id); });
}

template <int D>
void TemporalBroadPhaseN<D>::ray_cast(const RayN<D>& ray, RayCallback callback) const {
  float limit = 1.0f;
  const auto visit = [&](int id) {
    if (ray_box_fraction(ray, boxes_[id], limit) < 0.0f) return limit;
    const float r = callback(id, limit);
    if (r < limit) limit = r;
    return limit;
  };
  if (!grid_is_current()) {
    for (int i = 0; i < size() && limit > 0.0f; ++i) visit(i);
    return;
  }
  grid_.ray_cast(ray, [&](int id, float) { return visit(id); });
}

template <int D>
std::size_t TemporalBroadPhaseN<D>::memory_bytes() const noexcept {
  return (boxes_.capacity() + grown_.capacity()) * sizeof(AabbN<D>) +
         (speeds_.capacity() + scratch_.capacity()) * sizeof(float) +
         candidates_.capacity() * sizeof(BroadPair) + wake_.capacity() * sizeof(double) +
         grid_.memory_bytes();
}

template class TemporalBroadPhaseN<2>;
template class TemporalBroadPhaseN<3>;

}  // namespace collide
