#include <collide/broad/broad_phase.hpp>

#include <collide/core/error.hpp>
#include <collide/core/radix_sort.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace collide {

template <int D>
void validate_boxes(std::span<const AabbN<D>> boxes) {
  if (boxes.size() >= static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw InvalidInput("boxes: too many (" + std::to_string(boxes.size()) + ")");
  }
  static constexpr char kAxis[] = "xyz";
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const AabbN<D>& b = boxes[i];
    if (is_valid_box(b)) continue;
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

namespace {

/// Below this many pairs std::sort beats the radix sort's fixed cost (its digit histograms).
constexpr std::size_t kRadixSortMinPairs = 512;

}  // namespace

void sort_pairs(PairList& pairs) {
  PairList scratch;
  sort_pairs(pairs, scratch);
}

void sort_pairs(PairList& pairs, PairList& scratch) {
  int largest = 0;
  bool negative = false;
  for (const BroadPair& p : pairs) {
    largest = std::max({largest, p.first, p.second});
    negative |= (p.first | p.second) < 0;
  }
  if (pairs.size() < kRadixSortMinPairs || negative) {
    std::sort(pairs.begin(), pairs.end());
    return;
  }
  // Lexicographic order of non-negative (first, second) is the order of first * 2^w + second,
  // w the bits of the largest id.
  const int w = std::bit_width(static_cast<unsigned>(largest));
  radix_sort(pairs, scratch, 0, 2 * w, [w](const BroadPair& p) {
    return static_cast<std::uint64_t>(p.first) << w | static_cast<std::uint64_t>(p.second);
  });
}


}  // namespace collide
