#pragma once
// The order in which a one-query-per-iteration benchmark visits its pre-generated cases.

#include <cstdint>

namespace collide::bench {

/// Case indices in [0, mask] (mask + 1 a power of two) from a 32-bit linear congruential
/// generator (Numerical Recipes' constants), its bits 16 and up: the index sequence repeats only
/// after 2^17 cases or more. Cycling through the same N cases in the same order instead lets a
/// CPU whose branch predictor keeps a long history learn every case's branch outcomes: on the
/// AMD EPYC host of stop 49, 4096 ray casts replayed in order ran Box2D 2.4's polygon cast at
/// 5.9 ns, visited in this order at 39 ns, as on the Intel hosts either way. A game does not
/// replay its queries. The same seed on every side: each library sees the same cases in the
/// same order. The generator costs a multiply and an add per case, in parallel with the query.
class CaseOrder {
 public:
  explicit CaseOrder(std::uint32_t mask) noexcept : mask_(mask) {}
  [[nodiscard]] std::uint32_t next() noexcept {
    state_ = state_ * 1664525u + 1013904223u;
    return (state_ >> 16) & mask_;
  }

 private:
  std::uint32_t state_ = 2463534242u;
  std::uint32_t mask_;
};

}  // namespace collide::bench
