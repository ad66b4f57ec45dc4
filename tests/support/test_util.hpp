#pragma once
// Shared test helpers: glm-aware EXPECT macros, and the seeded random inputs of random.hpp.

#include <collide/core/math.hpp>

#include <gtest/gtest.h>

#include "support/random.hpp"

#define EXPECT_VEC2_NEAR(a, b, tol)                                         \
  do {                                                                      \
    const ::collide::Vec2 ev_a = (a);                                       \
    const ::collide::Vec2 ev_b = (b);                                       \
    EXPECT_LE(::collide::distance(ev_a, ev_b), (tol))                       \
        << #a " = (" << ev_a.x << ", " << ev_a.y << "), " #b " = (" << ev_b.x \
        << ", " << ev_b.y << ")";                                           \
  } while (false)

#define EXPECT_VEC3_NEAR(a, b, tol)                                                      \
  do {                                                                                   \
    const ::collide::Vec3 ev_a = (a);                                                    \
    const ::collide::Vec3 ev_b = (b);                                                    \
    EXPECT_LE(::collide::distance(ev_a, ev_b), (tol))                                    \
        << #a " = (" << ev_a.x << ", " << ev_a.y << ", " << ev_a.z << "), " #b " = ("    \
        << ev_b.x << ", " << ev_b.y << ", " << ev_b.z << ")";                            \
  } while (false)
