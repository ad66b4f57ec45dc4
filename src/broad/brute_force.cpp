#include <collide/broad/brute_force.hpp>

namespace collide {

template <int D>
void BruteForceN<D>::build(std::span<const AabbN<D>> boxes) {
  validate_boxes(boxes);
  boxes_.assign(boxes.begin(), boxes.end());
}

template <int D>
void BruteForceN<D>::find_pairs(PairList& pairs) const {
  pairs.clear();
  const int n = size();
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (overlap(boxes_[i], boxes_[j])) pairs.emplace_back(i, j);
    }
  }
}

template <int D>
void BruteForceN<D>::query(const AabbN<D>& box, QueryCallback callback) const {
  for (int i = 0; i < size(); ++i) {
    if (overlap(box, boxes_[i]) && !callback(i)) return;
  }
}

template <int D>
void BruteForceN<D>::query_point(const VecN<D>& point, QueryCallback callback) const {
  for (int i = 0; i < size(); ++i) {
    if (contains(boxes_[i], point) && !callback(i)) return;
  }
}

template <int D>
void BruteForceN<D>::ray_cast(const RayN<D>& ray, RayCallback callback) const {
  float limit = 1.0f;
  const SlabRayN<D> slab(ray);
  for (int i = 0; i < size(); ++i) {
    if (slab.fraction(boxes_[i], limit) < 0.0f) continue;
    const float r = callback(i, limit);
    if (r < limit) limit = r;
    if (limit <= 0.0f) return;
  }
}

template class BruteForceN<2>;
template class BruteForceN<3>;
static_assert(BroadPhase<BruteForceN<2>, 2> && BroadPhase<BruteForceN<3>, 3>);

}  // namespace collide
