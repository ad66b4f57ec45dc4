#pragma once
/// @file
/// `World3D`: the collision world in 3D (`WorldN<3>`, world.hpp, where the step and the queries
/// are described). Bodies are made of convex `Shape3D`s; statics of convex shapes, triangle
/// meshes (a level, with active edges: a body sliding over the seams gets no ghost contacts)
/// and height fields (`StaticShape3D`, the level shapes shared, not copied), and signed distance
/// fields (`StaticDef3::fields`, shared too). Y is up where a
/// convention is needed (height fields, `ground_check`'s usual `down`).

#include <collide/world/world.hpp>

namespace collide {

using StaticDef3 = StaticDefN<3>;          ///< a 3D static collider
using StaticField3 = StaticFieldN<3>;      ///< a 3D static's signed distance field (shared)
using BodyDef3 = BodyDefN<3>;              ///< a 3D body
using WorldOptions3 = WorldOptionsN<3>;    ///< options of a World3D
using Contact3 = ContactN<3>;              ///< a 3D contact of a step
using ContactEvent3 = ContactEventN<3>;    ///< a 3D contact event
using WorldRayHit3 = WorldRayHitN<3>;      ///< a 3D world ray cast hit
using LaserPath3 = LaserPathN<3>;          ///< a 3D laser and its reflections
using WorldCastHit3 = WorldCastHitN<3>;    ///< a 3D world shape cast hit
using World3D = WorldN<3>;                 ///< the 3D collision world

}  // namespace collide
