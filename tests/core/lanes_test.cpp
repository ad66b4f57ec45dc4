#include <collide/core/lanes.hpp>

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

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

// transpose turns four rows into four columns, every float moved as it is (bits, NaN included).
TEST(Lanes, TransposeMakesRowsColumns) {
  std::array<std::array<float, 4>, 4> rows{};
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) rows[r][k] = static_cast<float>(10 * r + k) - 0.5f;
  rows[2][1] = -0.0f;
  rows[3][0] = std::numeric_limits<float>::quiet_NaN();
  Lanes a = simd::load(rows[0]), b = simd::load(rows[1]), c = simd::load(rows[2]), d = simd::load(rows[3]);
  simd::transpose(a, b, c, d);
  const std::array<std::array<float, 4>, 4> columns{unpack(a), unpack(b), unpack(c), unpack(d)};
  for (int r = 0; r < 4; ++r) {
    for (int k = 0; k < 4; ++k) EXPECT_TRUE(same_bits(columns[k][r], rows[r][k])) << "row " << r << " lane " << k;
  }
}

#if defined(__SSE2__) || defined(_M_X64)
// ArgMax4 is the scalar scan `if (v > best) { best = v; index = i; }` in index order: the first
// index of the largest value, NaN never winning, kNone when nothing beat -infinity.
TEST(Lanes, ArgMax4IsTheFirstIndexOfTheLargestValueAsTheScalarScan) {
  std::mt19937 rng(7);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  int ties = 0;
  int nans = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int groups = 1 + static_cast<int>(rng() % 6);
    std::vector<float> v(static_cast<size_t>(4 * groups));
    for (float& x : v) {
      // Few distinct values so that ties across lanes are common; some NaN and -inf.
      const unsigned kind = rng() % 16;
      x = kind == 0 ? nan : kind == 1 ? -inf : static_cast<float>(static_cast<int>(rng() % 5) - 2);
    }
    if (trial % 97 == 0) std::fill(v.begin(), v.end(), nan);  // nothing beats -infinity
    float best = -inf;
    int index = simd::ArgMax4::kNone;
    int holding = 0;
    for (size_t i = 0; i < v.size(); ++i) {
      if (v[i] > best) {
        best = v[i];
        index = static_cast<int>(i);
      }
      nans += std::isnan(v[i]) ? 1 : 0;
    }
    simd::ArgMax4 scan;
    for (int g = 0; g < groups; ++g) scan.add(_mm_loadu_ps(v.data() + 4 * g));
    const simd::ArgMax4::Result r = scan.result();
    for (const float x : v) holding += x == best ? 1 : 0;
    ties += holding > 1 ? 1 : 0;
    ASSERT_EQ(r.index, index) << "trial " << trial;
    ASSERT_EQ(r.max, best) << "trial " << trial;
  }
  EXPECT_GT(ties, 1000);  // the lowest-index rule was exercised
  EXPECT_GT(nans, 1000);
}
#endif

}  // namespace
}  // namespace collide
