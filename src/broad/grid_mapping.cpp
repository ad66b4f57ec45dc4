#include <collide/broad/grid_mapping.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace collide {

template <int D>
AabbN<D> checked_bounds_of(std::span<const AabbN<D>> boxes) {
  if (boxes.empty()) {
    validate_boxes(boxes);
    return {};
  }
  // Plain min/max and one flag for all boxes (finite and ordered on every axis, written so NaN
  // fails): a loop the compiler vectorizes. The first bad box is named by validate_boxes.
  constexpr float kMax = std::numeric_limits<float>::max();
  VecN<D> lo = boxes[0].min, hi = boxes[0].max;
  bool good = boxes.size() < static_cast<std::size_t>(std::numeric_limits<int>::max());
  for (const AabbN<D>& b : boxes) {
    for (int k = 0; k < D; ++k) {
      good &= (b.min[k] <= b.max[k]) & (b.min[k] >= -kMax) & (b.max[k] <= kMax);
      lo[k] = b.min[k] < lo[k] ? b.min[k] : lo[k];
      hi[k] = b.max[k] > hi[k] ? b.max[k] : hi[k];
    }
  }
  if (!good) validate_boxes(boxes);  // throws
  return {lo, hi};
}

template <int D>
void sample_largest_sides(std::span<const AabbN<D>> boxes, std::vector<float>& out) {
  out.clear();
  // Every box up to kCellSizeSamples, else an even stride through the span (deterministic).
  const std::size_t n = boxes.size();
  const std::size_t samples = std::min<std::size_t>(n, kCellSizeSamples);
  for (std::size_t s = 0; s < samples; ++s) {
    const VecN<D> size = boxes[s * n / samples].size();
    float largest = size[0];
    for (int k = 1; k < D; ++k) largest = std::max(largest, size[k]);
    out.push_back(largest);
  }
}

template <int D>
float suggest_cell_size(std::span<const AabbN<D>> boxes, std::vector<float>& scratch) {
  return suggest_cell_size(boxes, bounds_of(boxes), scratch);
}

template <int D>
float suggest_cell_size(std::span<const AabbN<D>> boxes, const AabbN<D>& world,
                        std::vector<float>& scratch) {
  if (boxes.empty()) return 1.0f;
  sample_largest_sides(boxes, scratch);
  auto mid = scratch.begin() + static_cast<std::ptrdiff_t>(scratch.size() / 2);
  std::nth_element(scratch.begin(), mid, scratch.end());
  float size = 2.0f * *mid;

  const VecN<D> extent = world.size();
  float span = extent[0];
  float magnitude = 0.0f;
  for (int k = 0; k < D; ++k) {
    span = std::max(span, extent[k]);
    magnitude = std::max({magnitude, std::abs(world.min[k]), std::abs(world.max[k])});
  }
  if (!(size > 0.0f)) {
    // Points only: about one point per cell if they were spread evenly.
    const float per_axis = std::pow(static_cast<float>(boxes.size()), 1.0f / static_cast<float>(D));
    size = span / std::max(per_axis, 1.0f);
  }
  // A cell must stay well above the float spacing of the coordinates it divides.
  const float resolution = kCellSizeResolution * std::max(magnitude, 1e-30f);
  return std::max({size, resolution, std::numeric_limits<float>::min()});
}

template AabbN<2> checked_bounds_of<2>(std::span<const AabbN<2>>);
template AabbN<3> checked_bounds_of<3>(std::span<const AabbN<3>>);
template void sample_largest_sides<2>(std::span<const AabbN<2>>, std::vector<float>&);
template void sample_largest_sides<3>(std::span<const AabbN<3>>, std::vector<float>&);
template float suggest_cell_size<2>(std::span<const AabbN<2>>, std::vector<float>&);
template float suggest_cell_size<3>(std::span<const AabbN<3>>, std::vector<float>&);
template float suggest_cell_size<2>(std::span<const AabbN<2>>, const AabbN<2>&, std::vector<float>&);
template float suggest_cell_size<3>(std::span<const AabbN<3>>, const AabbN<3>&, std::vector<float>&);

}  // namespace collide
