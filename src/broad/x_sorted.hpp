#pragma once
// A few boxes kept sorted by their min x beside a grid that does not hold them (a grid's
// oversized boxes, the temporal broad phase's fast objects): a query or ray visits only those
// whose x extent can reach its own, found by a binary search, instead of all of them.

#include <algorithm>
#include <cmath>

namespace collide::detail {

/// Relative slack on a search interval along x, so that the float rounding of the callers'
/// intervals (a ray's end, lo - widest) never drops a box that reaches it (the box tests
/// decide; a box more is only a test more).
inline constexpr float kXRangeSlack = 1e-5f;

/// Calls visit(element) for each element of [first, last), sorted ascending by min_x(element)
/// (the min x of its box, every box at most `widest` wide along x), whose box may reach [lo, hi]
/// along x, in that order, until visit returns false; returns false when stopped. A box
/// reaching [lo, hi] has min x in [lo - widest, hi]. NaN bounds visit nothing.
template <class It, class MinX, class Visit>
bool visit_in_x_range(It first, It last, float lo, float hi, float widest, MinX&& min_x, Visit&& visit) {
  const float slack = kXRangeSlack * (std::abs(lo) + std::abs(hi) + widest);
  const float from = lo - widest - slack, to = hi + slack;
  auto it = std::lower_bound(first, last, from, [&](const auto& e, float x) { return min_x(e) < x; });
  for (; it != last && min_x(*it) <= to; ++it) {
    if (!visit(*it)) return false;
  }
  return true;
}

}  // namespace collide::detail
