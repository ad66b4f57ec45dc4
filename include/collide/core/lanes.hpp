#pragma once
/// @file
/// Four floats in one SIMD register, for code that does the same arithmetic on four points,
/// nodes, triangles or pieces of a shape at once (the triangle BVH's packets, the distance
/// field's band kernel, the capsule ray casts' side and end pieces).
/// With GCC and Clang, `Lanes` is the compiler's generic vector type (SSE on x86-64, NEON on
/// ARM): `+ - * /` and the comparisons work lane by lane, a comparison giving a `LaneMask` of
/// all-ones or zero lanes. Elsewhere it is a plain array with the same operators and loops, so
/// code written on `Lanes` builds everywhere and gives the same values, lane for lane, as the
/// scalar float expression it mirrors (the same operations in the same order).

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE__) && (defined(__GNUC__) || defined(__clang__))
#include <xmmintrin.h>
#endif
#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#endif

namespace collide::simd {

#if defined(__GNUC__) || defined(__clang__)
/// Four floats, one per lane.
using Lanes = float __attribute__((vector_size(16)));
/// Four lanes of all ones (true) or zero (false), as comparisons of `Lanes` give them.
using LaneMask = std::int32_t __attribute__((vector_size(16)));
#else
/// Four floats, one per lane.
struct Lanes {
  std::array<float, 4> v;
  float operator[](int k) const noexcept { return v[k]; }
  float& operator[](int k) noexcept { return v[k]; }
};
/// Four lanes of true or false, as comparisons of `Lanes` give them.
struct LaneMask {
  std::array<bool, 4> v;
};
#endif

/// The four floats of `a` (any alignment).
[[nodiscard]] inline Lanes load(const float* a) noexcept {
  Lanes v;
  std::memcpy(&v, a, sizeof(Lanes));
  return v;
}
/// The four floats of `a`.
[[nodiscard]] inline Lanes load(const std::array<float, 4>& a) noexcept { return load(a.data()); }
/// Writes the four lanes of `v` to a[0..3] (any alignment).
inline void store(float* a, Lanes v) noexcept { std::memcpy(a, &v, sizeof(Lanes)); }
/// `x` in every lane.
[[nodiscard]] inline Lanes splat(float x) noexcept;
/// The lanes a, b, c, d in that order.
[[nodiscard]] inline Lanes lanes(float a, float b, float c, float d) noexcept;
/// All ones in every lane if `b`, else zero.
[[nodiscard]] inline LaneMask mask(bool b) noexcept;
/// The mask of lanes a, b, c, d: all ones where true.
[[nodiscard]] inline LaneMask masks(bool a, bool b, bool c, bool d) noexcept;
/// Lane-wise square root (correctly rounded, as std::sqrt).
[[nodiscard]] inline Lanes sqrt(Lanes a) noexcept;
/// first, first + 1, first + 2, first + 3 as floats (each as float(int) gives it: exact below
/// 2^24).
[[nodiscard]] inline Lanes iota(int first) noexcept;
/// `a` where `m` is set, `b` elsewhere.
[[nodiscard]] inline Lanes select(LaneMask m, Lanes a, Lanes b) noexcept;
[[nodiscard]] inline LaneMask select(LaneMask m, LaneMask a, LaneMask b) noexcept;
/// Lane-wise minimum and maximum; `b` where `a` is NaN (as SSE minps / maxps do: a ray's slab
/// test relies on it to ignore the NaN of an axis the ray does not move along).
[[nodiscard]] inline Lanes min(Lanes a, Lanes b) noexcept;
[[nodiscard]] inline Lanes max(Lanes a, Lanes b) noexcept;
/// Bit k set where lane k of `m` is.
[[nodiscard]] inline unsigned lane_bits(LaneMask m) noexcept;
/// The smallest lane, in every lane (NaN lanes as min gives them).
[[nodiscard]] inline Lanes horizontal_min(Lanes a) noexcept;
/// The lanes a[i0], a[i1], a[i2], a[i3].
template <int i0, int i1, int i2, int i3>
[[nodiscard]] inline Lanes shuffle(Lanes a) noexcept;
/// Lane `k` of `a` in every lane.
template <int k>
[[nodiscard]] inline Lanes broadcast(Lanes a) noexcept {
  return shuffle<k, k, k, k>(a);
}
/// `b`'s lane 0 with `a`'s lanes 1 to 3 (SSE's movss between registers).
[[nodiscard]] inline Lanes with_lane0(Lanes a, Lanes b) noexcept;
/// Rows a, b, c, d of a 4 x 4 matrix become its columns: lane k of `a` after is lane 0 of the
/// k-th row before, and so on (SSE's _MM_TRANSPOSE4_PS): four records stored one per `Lanes`
/// (a box's extents x, y, z) turned into one `Lanes` per field.
inline void transpose(Lanes& a, Lanes& b, Lanes& c, Lanes& d) noexcept;

#if defined(__GNUC__) || defined(__clang__)
inline Lanes splat(float x) noexcept { return Lanes{x, x, x, x}; }
inline Lanes lanes(float a, float b, float c, float d) noexcept { return Lanes{a, b, c, d}; }
inline Lanes iota(int first) noexcept {
  using Ints = std::int32_t __attribute__((vector_size(16)));
  return __builtin_convertvector((Ints{first, first, first, first} + Ints{0, 1, 2, 3}), Lanes);
}
inline LaneMask masks(bool a, bool b, bool c, bool d) noexcept { return LaneMask{-a, -b, -c, -d}; }
inline Lanes sqrt(Lanes a) noexcept {
#if defined(__SSE__)
  return reinterpret_cast<Lanes>(_mm_sqrt_ps(reinterpret_cast<__m128>(a)));
#else
  return Lanes{std::sqrt(a[0]), std::sqrt(a[1]), std::sqrt(a[2]), std::sqrt(a[3])};
#endif
}
inline Lanes select(LaneMask m, Lanes a, Lanes b) noexcept { return m ? a : b; }
inline LaneMask select(LaneMask m, LaneMask a, LaneMask b) noexcept { return m ? a : b; }
inline Lanes min(Lanes a, Lanes b) noexcept { return a < b ? a : b; }
inline Lanes max(Lanes a, Lanes b) noexcept { return a > b ? a : b; }
inline unsigned lane_bits(LaneMask m) noexcept {
#if defined(__SSE__)
  return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(m)));
#else
  return (m[0] & 1u) | (m[1] & 2u) | (m[2] & 4u) | (m[3] & 8u);
#endif
}
inline Lanes horizontal_min(Lanes a) noexcept {
  const Lanes b = min(a, __builtin_shufflevector(a, a, 1, 0, 3, 2));
  return min(b, __builtin_shufflevector(b, b, 2, 3, 0, 1));
}
template <int i0, int i1, int i2, int i3>
inline Lanes shuffle(Lanes a) noexcept {
  return __builtin_shufflevector(a, a, i0, i1, i2, i3);
}
inline Lanes with_lane0(Lanes a, Lanes b) noexcept { return __builtin_shufflevector(a, b, 4, 1, 2, 3); }
inline void transpose(Lanes& a, Lanes& b, Lanes& c, Lanes& d) noexcept {
  const Lanes ab_low = __builtin_shufflevector(a, b, 0, 4, 1, 5), cd_low = __builtin_shufflevector(c, d, 0, 4, 1, 5);
  const Lanes ab_high = __builtin_shufflevector(a, b, 2, 6, 3, 7), cd_high = __builtin_shufflevector(c, d, 2, 6, 3, 7);
  a = __builtin_shufflevector(ab_low, cd_low, 0, 1, 4, 5);
  b = __builtin_shufflevector(ab_low, cd_low, 2, 3, 6, 7);
  c = __builtin_shufflevector(ab_high, cd_high, 0, 1, 4, 5);
  d = __builtin_shufflevector(ab_high, cd_high, 2, 3, 6, 7);
}
#else
/// The lanes f(0), f(1), f(2), f(3): the portable form's loop.
template <class F>
[[nodiscard]] inline Lanes lanewise(F f) noexcept {
  return {{f(0), f(1), f(2), f(3)}};
}
/// The mask of pred(0..3): the portable form's comparisons.
template <class F>
[[nodiscard]] inline LaneMask maskwise(F f) noexcept {
  return {{f(0), f(1), f(2), f(3)}};
}
/// Lane-wise arithmetic.
inline Lanes operator+(Lanes a, Lanes b) noexcept { return lanewise([&](int k) { return a.v[k] + b.v[k]; }); }
inline Lanes operator-(Lanes a, Lanes b) noexcept { return lanewise([&](int k) { return a.v[k] - b.v[k]; }); }
inline Lanes operator*(Lanes a, Lanes b) noexcept { return lanewise([&](int k) { return a.v[k] * b.v[k]; }); }
inline Lanes operator/(Lanes a, Lanes b) noexcept { return lanewise([&](int k) { return a.v[k] / b.v[k]; }); }
inline Lanes operator-(Lanes a) noexcept { return lanewise([&](int k) { return -a.v[k]; }); }
/// Lane-wise comparisons.
inline LaneMask operator<(Lanes a, Lanes b) noexcept { return maskwise([&](int k) { return a.v[k] < b.v[k]; }); }
inline LaneMask operator>(Lanes a, Lanes b) noexcept { return maskwise([&](int k) { return a.v[k] > b.v[k]; }); }
inline LaneMask operator<=(Lanes a, Lanes b) noexcept { return maskwise([&](int k) { return a.v[k] <= b.v[k]; }); }
inline LaneMask operator>=(Lanes a, Lanes b) noexcept { return maskwise([&](int k) { return a.v[k] >= b.v[k]; }); }
inline LaneMask operator==(Lanes a, Lanes b) noexcept { return maskwise([&](int k) { return a.v[k] == b.v[k]; }); }
/// Lane-wise and / or / not of masks.
inline LaneMask operator&(LaneMask a, LaneMask b) noexcept { return maskwise([&](int k) { return a.v[k] && b.v[k]; }); }
inline LaneMask operator|(LaneMask a, LaneMask b) noexcept { return maskwise([&](int k) { return a.v[k] || b.v[k]; }); }
inline LaneMask operator~(LaneMask a) noexcept { return maskwise([&](int k) { return !a.v[k]; }); }
inline Lanes splat(float x) noexcept { return {{x, x, x, x}}; }
inline Lanes lanes(float a, float b, float c, float d) noexcept { return {{a, b, c, d}}; }
inline Lanes iota(int first) noexcept {
  return lanewise([&](int k) { return static_cast<float>(first + k); });
}
inline LaneMask masks(bool a, bool b, bool c, bool d) noexcept { return {{a, b, c, d}}; }
inline Lanes sqrt(Lanes a) noexcept { return lanewise([&](int k) { return std::sqrt(a.v[k]); }); }
inline Lanes select(LaneMask m, Lanes a, Lanes b) noexcept { return lanewise([&](int k) { return m.v[k] ? a.v[k] : b.v[k]; }); }
inline LaneMask select(LaneMask m, LaneMask a, LaneMask b) noexcept { return maskwise([&](int k) { return m.v[k] ? a.v[k] : b.v[k]; }); }
inline Lanes min(Lanes a, Lanes b) noexcept { return lanewise([&](int k) { return a.v[k] < b.v[k] ? a.v[k] : b.v[k]; }); }
inline Lanes max(Lanes a, Lanes b) noexcept { return lanewise([&](int k) { return a.v[k] > b.v[k] ? a.v[k] : b.v[k]; }); }
inline unsigned lane_bits(LaneMask m) noexcept {
  return unsigned(m.v[0]) | unsigned(m.v[1]) << 1 | unsigned(m.v[2]) << 2 | unsigned(m.v[3]) << 3;
}
inline Lanes horizontal_min(Lanes a) noexcept {
  const Lanes b = min(a, lanes(a.v[1], a.v[0], a.v[3], a.v[2]));
  return min(b, lanes(b.v[2], b.v[3], b.v[0], b.v[1]));
}
template <int i0, int i1, int i2, int i3>
inline Lanes shuffle(Lanes a) noexcept {
  return lanes(a.v[i0], a.v[i1], a.v[i2], a.v[i3]);
}
inline Lanes with_lane0(Lanes a, Lanes b) noexcept {
  a.v[0] = b.v[0];
  return a;
}
inline void transpose(Lanes& a, Lanes& b, Lanes& c, Lanes& d) noexcept {
  const Lanes r0 = a, r1 = b, r2 = c, r3 = d;
  a = lanes(r0.v[0], r1.v[0], r2.v[0], r3.v[0]);
  b = lanes(r0.v[1], r1.v[1], r2.v[1], r3.v[1]);
  c = lanes(r0.v[2], r1.v[2], r2.v[2], r3.v[2]);
  d = lanes(r0.v[3], r1.v[3], r2.v[3], r3.v[3]);
}
#endif

inline LaneMask mask(bool b) noexcept { return splat(b ? 1.0f : 0.0f) > splat(0.0f); }

#if defined(__SSE2__) || defined(_M_X64)
/// The largest of values fed four at a time and the lowest index that holds it, the argmax of
/// a scan (lane j of the k-th `add` is index 4k + j), in SSE2 registers without branches: each
/// lane keeps its running best and the first index that reached it (a strict '>': a NaN value
/// never wins and keeps the old best, as maxps does), and `result` merges the lanes, the
/// maximum first, then the lowest index among the lanes that hold it. So the answer is the
/// scalar scan's `if (v > best)` in index order. (A scalar merge of the lanes mispredicted about
/// once per call and cost more than a 64-point scan: 22 -> 8 ns, bench_convex_hull.) Serves the
/// support scans of ConvexProxy (2D) and ConvexHull (3D) and the hull contact's face query.
/// Indices below kNone (the merge takes 16-bit minima: SSE2 has no 32-bit one).
class ArgMax4 {
 public:
  /// The index reported when no value beat -infinity (nothing fed, or every value NaN); above
  /// any index a caller may feed.
  static constexpr int kNone = 0x7fff;

  /// The largest value fed (-infinity if none) and the lowest index holding it (or kNone).
  struct Result {
    float max;
    int index;
  };

  /// Feeds the next four values.
  void add(__m128 values) noexcept {
    const __m128i better = _mm_castps_si128(_mm_cmpgt_ps(values, best_));  // false for NaN
    best_ = _mm_max_ps(values, best_);  // a NaN value keeps the old best
    best_index_ = _mm_or_si128(_mm_and_si128(better, index_), _mm_andnot_si128(better, best_index_));
    index_ = _mm_add_epi32(index_, _mm_set1_epi32(4));
  }

  /// The lanes merged.
  [[nodiscard]] Result result() const noexcept {
    // The maximum over the lanes, in all of them.
    __m128 top = _mm_max_ps(best_, _mm_shuffle_ps(best_, best_, _MM_SHUFFLE(1, 0, 3, 2)));
    top = _mm_max_ps(top, _mm_shuffle_ps(top, top, _MM_SHUFFLE(2, 3, 0, 1)));
    // The lowest index among the lanes holding it.
    const __m128i holds = _mm_castps_si128(_mm_cmpeq_ps(best_, top));
    __m128i candidate = _mm_or_si128(_mm_and_si128(holds, best_index_),
                                     _mm_andnot_si128(holds, _mm_set1_epi32(kNone)));
    candidate = _mm_min_epi16(candidate, _mm_shuffle_epi32(candidate, _MM_SHUFFLE(1, 0, 3, 2)));
    candidate = _mm_min_epi16(candidate, _mm_shuffle_epi32(candidate, _MM_SHUFFLE(2, 3, 0, 1)));
    return {_mm_cvtss_f32(top), _mm_cvtsi128_si32(candidate) & kNone};
  }

 private:
  __m128 best_ = _mm_set1_ps(-HUGE_VALF);
  __m128i best_index_ = _mm_set1_epi32(kNone);
  __m128i index_ = _mm_setr_epi32(0, 1, 2, 3);
};
#endif

}  // namespace collide::simd
