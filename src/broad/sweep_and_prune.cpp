#include <collide/broad/sweep_and_prune.hpp>

#include <algorithm>
#include <cmath>

namespace collide {

namespace {
/// Relative widening of the look-back window of a query: far above float rounding (1e-7).
constexpr float kSweepLookBackSlack = 1e-5f;
}  // namespace

template <int D>
void SweepAndPruneN<D>::build(std::span<const AabbN<D>> boxes) {
  validate_boxes(boxes);
  // Axis of largest variance of the centres (in double: far-from-origin worlds).
  double sum[D] = {}, sum_sq[D] = {};
  for (const AabbN<D>& b : boxes) {
    const VecN<D> c = b.center();
    for (int k = 0; k < D; ++k) {
      sum[k] += c[k];
      sum_sq[k] += static_cast<double>(c[k]) * c[k];
    }
  }
  axis_ = 0;
  double best = -1.0;
  const double n = std::max<double>(1.0, static_cast<double>(boxes.size()));
  for (int k = 0; k < D; ++k) {
    const double variance = sum_sq[k] / n - (sum[k] / n) * (sum[k] / n);
    if (variance > best) {
      best = variance;
      axis_ = k;
    }
  }
  items_.resize(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) items_[i] = {boxes[i], static_cast<int>(i)};
  std::sort(items_.begin(), items_.end(), [this](const Item& a, const Item& b) { return before(a, b); });
  refresh_longest();
}

template <int D>
void SweepAndPruneN<D>::update(std::span<const AabbN<D>> boxes) {
  if (boxes.size() != items_.size()) {
    build(boxes);
    return;
  }
  validate_boxes(boxes);
  for (Item& item : items_) item.box = boxes[item.id];
  // Insertion sort: each item slides back past the few that it overtook since the last frame.
  for (std::size_t i = 1; i < items_.size(); ++i) {
    if (!before(items_[i], items_[i - 1])) continue;
    const Item moving = items_[i];
    std::size_t j = i;
    do {
      items_[j] = items_[j - 1];
      --j;
    } while (j > 0 && before(moving, items_[j - 1]));
    items_[j] = moving;
  }
  refresh_longest();
}

template <int D>
void SweepAndPruneN<D>::refresh_longest() noexcept {
  longest_ = 0.0f;
  for (const Item& item : items_) longest_ = std::max(longest_, item.box.max[axis_] - item.box.min[axis_]);
}

template <int D>
void SweepAndPruneN<D>::find_pairs(PairList& pairs) const {
  pairs.clear();
  const std::size_t n = items_.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Item& a = items_[i];
    const float end = a.box.max[axis_];
    for (std::size_t j = i + 1; j < n && items_[j].box.min[axis_] <= end; ++j) {
      const Item& b = items_[j];
      if (overlap(a.box, b.box)) pairs.emplace_back(std::min(a.id, b.id), std::max(a.id, b.id));
    }
  }
}

template <int D>
template <class Visit>
void SweepAndPruneN<D>::scan(float lo, float hi, Visit&& visit) const {
  // Look back by the longest box, plus a little: the rounding of `lo - longest_` and of the
  // box lengths must not hide a box that reaches lo.
  const float from = lo - longest_ - kSweepLookBackSlack * (std::abs(lo) + longest_);
  auto it = std::lower_bound(items_.begin(), items_.end(), from,
                             [this](const Item& item, float v) { return item.box.min[axis_] < v; });
  for (; it != items_.end() && it->box.min[axis_] <= hi; ++it) {
    if (!visit(*it)) return;
  }
}

template <int D>
void SweepAndPruneN<D>::query(const AabbN<D>& box, QueryCallback callback) const {
  scan(box.min[axis_], box.max[axis_],
       [&](const Item& item) { return !overlap(box, item.box) || callback(item.id); });
}

template <int D>
void SweepAndPruneN<D>::query_point(const VecN<D>& point, QueryCallback callback) const {
  scan(point[axis_], point[axis_],
       [&](const Item& item) { return !contains(item.box, point) || callback(item.id); });
}

template <int D>
void SweepAndPruneN<D>::ray_cast(const RayN<D>& ray, RayCallback callback) const {
  float limit = 1.0f;
  const float a = ray.origin[axis_];
  const float b = ray.origin[axis_] + ray.translation[axis_];
  // The end b is rounded, and so is the fraction at which ray_box_fraction meets a box: a box
  // starting a few float spacings past b may count as met at fraction 1 (at 1e38 a spacing is
  // 1e31). Look ahead by the same relative slack as the look-back (an infinite slack when the
  // sum overflows: then every box is a candidate, still exact).
  const float ahead = kSweepLookBackSlack * (std::abs(a) + std::abs(ray.translation[axis_]));
  const SlabRayN<D> slab(ray);
  scan(std::min(a, b), std::max(a, b) + ahead, [&](const Item& item) {
    if (slab.fraction(item.box, limit) < 0.0f) return true;
    const float r = callback(item.id, limit);
    if (r < limit) limit = r;
    return limit > 0.0f;
  });
}

template class SweepAndPruneN<2>;
template class SweepAndPruneN<3>;
static_assert(BroadPhase<SweepAndPruneN<2>, 2> && BroadPhase<SweepAndPruneN<3>, 3>);

}  // namespace collide
