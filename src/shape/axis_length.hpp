#pragma once
// Private to src/shape: the one check that a segment's or capsule's ends are apart, shared by
// the 2D and 3D constructors.

#include <collide/core/error.hpp>
#include <collide/core/math.hpp>

#include <limits>
#include <string>

namespace collide::detail {

/// Throws InvalidInput "<what>: a and b coincide<hint>" unless |b - a|^2 is at least the
/// smallest normal float: queries divide by it, and a squared length that underflows to 0 or a
/// denormal (ends closer than about 1e-19) made them answer NaN (found by fuzz_shapes).
template <class V>
void check_axis(V a, V b, const char* what, const char* hint = "") {
  if (!(length_squared(b - a) >= std::numeric_limits<float>::min())) {
    throw InvalidInput(std::string(what) + ": a and b coincide" + hint +
                       (a == b ? "" : " (closer than about 1e-19: their squared distance underflows float)"));
  }
}

}  // namespace collide::detail
