#pragma once
/// @file
/// The range of coordinates within which queries promise finite results.

namespace collide {

/// Queries (overlap, distance, contact, ray and shape casts) give finite results for shapes whose
/// bounds lie within this magnitude of the origin, placed by transforms within it (world units;
/// 1e9 m is a million km, where a float is already 64 m coarse). Beyond it the products of
/// coordinates the algorithms form (squared lengths, cross products of cross products) may
/// overflow: queries still never throw nor crash, but may answer infinities or NaN (`collide
/// query` reports "no finite answer"). Constructors accept any finite values; refusing at load
/// is the readers' choice (e.g. kMaxTiledCoordinate). fuzz_shapes checks the promise
/// (fuzz/shapes_check.hpp).
inline constexpr float kFiniteQueryRange = 1e9f;

}  // namespace collide
