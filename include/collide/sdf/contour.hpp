#pragma once
/// @file
/// Contours of a 2D grid of samples (a 2D distance field, a slice of a 3D one): where the
/// bilinear interpolation of the samples crosses a level, as segments, by marching squares
/// (Lorensen & Cline, "Marching cubes", SIGGRAPH 1987, in 2D). Header-only, no allocation: the
/// segments go to a callback, so a picture and a world's debug drawing share one routine.

#include <collide/core/aabb.hpp>  // Vec2

#include <array>

namespace collide {

/// Calls `emit(Vec2 a, Vec2 b)` for each segment of the contour where the samples cross
/// `level`. Sample (i, j), i in [0, width) and j in [0, height), is `value(i, j)` (a float) and
/// lies at origin + spacing * (i, j) (world units, in the plane). In each cell the crossings on
/// its edges are found by linear interpolation between the corners and joined in pairs; a saddle
/// cell (opposite corners below the level) is resolved by the mean of its corners, the value at
/// its centre. A sample exactly at `level` counts as above it. Nothing for width or height < 2.
template <class Value, class Emit>
void march_squares(int width, int height, Vec2 origin, float spacing, float level, Value&& value, Emit&& emit) {
  const auto at = [&](int i, int j) { return static_cast<float>(value(i, j)) - level; };
  const auto world = [&](float i, float j) { return origin + spacing * Vec2{i, j}; };
  // Where the edge from corner p (value a) to corner q (value b) crosses the level.
  const auto cross = [](Vec2 p, float a, Vec2 q, float b) { return p + (a / (a - b)) * (q - p); };
  for (int j = 0; j + 1 < height; ++j) {
    for (int i = 0; i + 1 < width; ++i) {
      // Corners counter-clockwise from (i, j): 0 (i, j), 1 (i+1, j), 2 (i+1, j+1), 3 (i, j+1).
      // std::array, not C arrays: GCC 12 with -fsanitize=undefined (the sanitize preset)
      // miscompiled C arrays here (garbage indices reported, no segments emitted).
      const std::array<float, 4> v = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
      int code = 0;
      for (int k = 0; k < 4; ++k) code |= (v[k] < 0.0f ? 1 : 0) << k;
      if (code == 0 || code == 15) continue;
      const float fi = static_cast<float>(i), fj = static_cast<float>(j);
      const std::array<Vec2, 4> c = {world(fi, fj), world(fi + 1, fj), world(fi + 1, fj + 1), world(fi, fj + 1)};
      // The crossing on edge k (corner k to k + 1), for edges whose ends differ in sign.
      const auto edge = [&](int k) { return cross(c[k], v[k], c[(k + 1) % 4], v[(k + 1) % 4]); };
      if (code == 5 || code == 10) {  // saddle: opposite corners below; the centre decides
        const bool centre_below = 0.25f * (v[0] + v[1] + v[2] + v[3]) < 0.0f;
        // Centre below: the below corners join through it, the contour cuts off the above ones;
        // centre above: it cuts off the below ones. Either way around corners 1 and 3 when:
        const bool around_1_3 = (code == 5) == centre_below;
        if (around_1_3) {
          emit(edge(0), edge(1));
          emit(edge(2), edge(3));
        } else {
          emit(edge(3), edge(0));
          emit(edge(1), edge(2));
        }
        continue;
      }
      std::array<Vec2, 2> ends{};
      int n = 0;
      for (int k = 0; k < 4 && n < 2; ++k) {
        if (((code >> k) & 1) != ((code >> ((k + 1) % 4)) & 1)) ends[n++] = edge(k);
      }
      emit(ends[0], ends[1]);
    }
  }
}

}  // namespace collide
