#pragma once
/// @file
/// `World2D`: the collision world in 2D (`WorldN<2>`, world.hpp, where the step and the queries
/// are described). Statics and bodies are made of `Shape2D`s; a concave outline goes in as the
/// pieces of `convex_pieces`; a static may also hold signed distance fields (`StaticDef::fields`).

#include <collide/world/world.hpp>

#include <span>
#include <string_view>
#include <vector>

namespace collide {

using StaticDef = StaticDefN<2>;          ///< a 2D static collider
using StaticField = StaticFieldN<2>;      ///< a 2D static's signed distance field (shared)
using BodyDef = BodyDefN<2>;              ///< a 2D body
using WorldOptions = WorldOptionsN<2>;    ///< options of a World2D
using Contact = ContactN<2>;              ///< a 2D contact of a step
using ContactEvent = ContactEventN<2>;    ///< a 2D contact event
using WorldRayHit = WorldRayHitN<2>;      ///< a 2D world ray cast hit
using LaserPath = LaserPathN<2>;          ///< a 2D laser and its reflections
using WorldCastHit = WorldCastHitN<2>;    ///< a 2D world shape cast hit
using World2D = WorldN<2>;                ///< the 2D collision world

/// The convex pieces of a simple polygon outline (either winding; concave allowed), for
/// StaticDef/BodyDef shapes: one piece when it is convex, else `decompose_convex` (ear clipping
/// + Hertel-Mehlhorn). Throws InvalidInput naming `name` for a self-intersecting, degenerate or
/// non-finite outline.
[[nodiscard]] std::vector<Shape2D> convex_pieces(std::span<const Vec2> outline,
                                                 std::string_view name = "polygon");

}  // namespace collide
