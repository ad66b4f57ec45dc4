#include <collide/broad/broad_phase.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace collide {

template <int D>
void validate_boxes(std::span<const AabbN<D>> boxes) {
  if (boxes.size() >= static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw InvalidInput("boxes: too many (" + std::to_string(boxes.size()) + ")");
  }
  static constexpr char kAxis[] = "xyz";
  constexpr float kMax = std::numeric_limits<float>::max();
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const AabbN<D>& b = boxes[i];
    // Fast path, written so NaN fails: finite and ordered on every axis.
    bool good = true;
    for (int k = 0; k < D; ++k) {
      good &= (b.min[k] <= b.max[k]) & (b.min[k] >= -kMax) & (b.max[k] <= kMax);
    }
    if (good) continue;
    for (int k = 0; k < D; ++k) {
      if (!std::isfinite(b.min[k]) || !std::isfinite(b.max[k])) {
        throw InvalidInput("box " + std::to_string(i) + ": coordinate not finite");
      }
      if (b.min[k] > b.max[k]) {
        throw InvalidInput("box " + std::to_string(i) + ": min." + kAxis[k] + " > max." +
                           kAxis[k]);
      }
    }
  }
}

template void validate_boxes<2>(std::span<const AabbN<2>>);
template void validate_boxes<3>(std::span<const AabbN<3>>);

void sort_pairs(PairList& pairs) { std::sort(pairs.begin(), pairs.end()); }


}  // namespace collide
