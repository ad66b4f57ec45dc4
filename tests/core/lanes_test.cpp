#include <collide/core/lanes.hpp>

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>

namespace collide {
namespace {

using simd::Lanes;

std::array<float, 4> unpack(Lanes v) {
  std::array<float, 4> out{};
  simd::store(out.data(), v);
  return out;
}

bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

// Every lane of an expression on Lanes is the float expression on that lane's values, bit for
// bit (the band kernel's fields rely on it), NaN and infinities included.
TEST(Lanes, ArithmeticAndSelectsAreTheScalarExpressionLaneByLane) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1e3f, 1e3f);
  const float specials[] = {0.0f, -0.0f, std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                            1e-40f};
  for (int round = 0; round < 2000; ++round) {
    std::array<float, 4> a{}, b{}, c{};
    for (int k = 0; k < 4; ++k) {
      a[k] = round % 5 == 0 ? specials[(round / 5 + k) % 6] : u(rng);
      b[k] = u(rng);
      c[k] = round % 7 == 0 ? specials[(round / 7 + 2 * k) % 6] : u(rng);
    }
    const Lanes la = simd::load(a), lb = simd::load(b), lc = simd::load(c);
    const auto r = unpack(simd::select(la > lb, la * lb - lc, (la + lc) / lb));
    const auto mn = unpack(simd::min(la, lc));
    const auto mx = unpack(simd::max(la, lc));
    const auto root = unpack(simd::sqrt(-la));
    const unsigned bits = simd::lane_bits((la >= lb) & (lc < lb));
    const unsigned either = simd::lane_bits(simd::select(la <= lb, ~(lc == lb), la == la) | (la < lc));
    for (int k = 0; k < 4; ++k) {
      const float want = a[k] > b[k] ? a[k] * b[k] - c[k] : (a[k] + c[k]) / b[k];
      EXPECT_TRUE(same_bits(r[k], want)) << r[k] << " vs " << want;
      // min and max give b where a is NaN, as SSE does (a < b, a > b false).
      EXPECT_TRUE(same_bits(mn[k], a[k] < c[k] ? a[k] : c[k]));
      EXPECT_TRUE(same_bits(mx[k], a[k] > c[k] ? a[k] : c[k]));
      const float s = std::sqrt(-a[k]);
      EXPECT_TRUE(same_bits(root[k], s) || (std::isnan(root[k]) && std::isnan(s)));
      EXPECT_EQ((bits >> k) & 1u, unsigned(a[k] >= b[k] && c[k] < b[k]));
      EXPECT_EQ((either >> k) & 1u, unsigned((a[k] <= b[k] ? !(c[k] == b[k]) : a[k] == a[k]) || a[k] < c[k]));
    }
  }
}

TEST(Lanes, NaNInTheFirstOperandOfMinAndMaxGivesTheSecond) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const auto mn = unpack(simd::min(simd::lanes(nan, 1.0f, nan, -2.0f), simd::splat(0.5f)));
  const auto mx = unpack(simd::max(simd::lanes(nan, 1.0f, nan, -2.0f), simd::splat(0.5f)));
  EXPECT_EQ(mn, (std::array<float, 4>{0.5f, 0.5f, 0.5f, -2.0f}));
  EXPECT_EQ(mx, (std::array<float, 4>{0.5f, 1.0f, 0.5f, 0.5f}));
}

TEST(Lanes, IotaMaskAndHorizontalMin) {
  for (const int first : {0, -3, 17, (1 << 24) - 4, -(1 << 24)}) {
    const auto v = unpack(simd::iota(first));
    for (int k = 0; k < 4; ++k) EXPECT_EQ(v[k], static_cast<float>(first + k));
  }
  EXPECT_EQ(simd::lane_bits(simd::mask(true)), 0xfu);
  EXPECT_EQ(simd::lane_bits(simd::mask(false)), 0u);
  EXPECT_EQ(simd::lane_bits(simd::masks(true, false, true, true)), 0xdu);
  EXPECT_EQ(simd::lane_bits(~simd::masks(true, false, true, true)), 0x2u);
  const auto m = unpack(simd::select(simd::mask(true), simd::splat(1.0f), simd::splat(2.0f)));
  EXPECT_EQ(m, (std::array<float, 4>{1.0f, 1.0f, 1.0f, 1.0f}));
  for (int at = 0; at < 4; ++at) {
    std::array<float, 4> a{3.0f, 5.0f, 4.0f, 6.0f};
    a[at] = -1.0f;
    const auto h = unpack(simd::horizontal_min(simd::load(a)));
    EXPECT_EQ(h, (std::array<float, 4>{-1.0f, -1.0f, -1.0f, -1.0f}));
    EXPECT_EQ(simd::lane_bits(simd::load(a) == simd::horizontal_min(simd::load(a))), 1u << at);
  }
}

}  // namespace
}  // namespace collide
