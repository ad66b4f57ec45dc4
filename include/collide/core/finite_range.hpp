#pragma once
/// @file
/// The range of coordinates within which queries promise finite results.

namespace collide {

/// Queries (overlap, distance, contact, ray and shape casts) give finite results for shapes whose
/// bounds lie within this magnitude of the origin, placed by transforms within it (world units;
/// 2^30 = 1073741824: a million km in metres, where a float is already 64 m coarse). Why this
/// value: the narrow phase multiplies up to four coordinate differences (2D GJK's triangle region
/// test: a triangle's area times a cross product); within +-2^30 every such product stays below
/// 2^128, finite in float. Beyond it those products may overflow: queries still never throw nor
/// crash, but may answer infinities or NaN (`collide query` reports "no finite answer").
/// Constructors accept any finite values; refusing at load is the caller's choice: World2D
/// refuses beyond it (kMaxWorldCoordinate is this range), the Tiled reader far earlier
/// (kMaxTiledCoordinate). fuzz_shapes and fuzz_obj_mesh check the promise (fuzz/shapes_check.hpp).
inline constexpr float kFiniteQueryRange = 0x1p30f;

}  // namespace collide
