#include <collide/broad/grid_mapping.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace collide {

template <int D>
float suggest_cell_size(std::span<const AabbN<D>> boxes, std::vector<float>& scratch) {
  if (boxes.empty()) return 1.0f;
  scratch.clear();
  for (const AabbN<D>& b : boxes) {
    const VecN<D> s = b.size();
    float largest = s[0];
    for (int k = 1; k < D; ++k) largest = std::max(largest, s[k]);
    scratch.push_back(largest);
  }
  auto mid = scratch.begin() + static_cast<std::ptrdiff_t>(scratch.size() / 2);
  std::nth_element(scratch.begin(), mid, scratch.end());
  float size = 2.0f * *mid;

  const AabbN<D> world = bounds_of(boxes);
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
  const float resolution = 1e-5f * std::max(magnitude, 1e-30f);
  return std::max({size, resolution, std::numeric_limits<float>::min()});
}

template float suggest_cell_size<2>(std::span<const AabbN<2>>, std::vector<float>&);
template float suggest_cell_size<3>(std::span<const AabbN<3>>, std::vector<float>&);

}  // namespace collide
