#pragma once
/// @file
/// Least-significant-digit radix sort of records by an unsigned 64-bit key: stable,
/// O(n) per 11-bit digit, one read pass for all digit histograms, and passes whose digit is the
/// same for every record skipped. (Knuth, TAOCP vol. 3, 5.2.5.) Shared by the broad phases'
/// pair lists and grids and, through sort_edge_uses, by TriangleMesh's active edges and the walk
/// mesh build; a game building its own adjacency or sorting keyed records may call them too.

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace collide {

/// Bits of the key sorted per pass (2048 buckets: the counts of all passes fit the L1 cache).
inline constexpr int kRadixDigitBits = 11;

/// Sorts `data` by bits [first_bit, first_bit + key_bits) of `key_of(record)` (an unsigned
/// 64-bit value; first_bit + key_bits <= 64), stably: records of equal bits keep their order.
/// `scratch` is reused storage. Allocates only when `scratch` must grow; reports no errors.
template <class Record, class KeyOf>
void radix_sort(std::vector<Record>& data, std::vector<Record>& scratch, int first_bit, int key_bits,
                KeyOf&& key_of) {
  constexpr std::size_t kBuckets = std::size_t{1} << kRadixDigitBits;
  constexpr int kMaxPasses = (64 + kRadixDigitBits - 1) / kRadixDigitBits;
  const int passes = (key_bits + kRadixDigitBits - 1) / kRadixDigitBits;
  const std::size_t n = data.size();
  if (passes == 0 || n < 2) return;

  // Each pass's digit: kRadixDigitBits bits, the last one only what is left of the range (bits
  // above it do not count).
  std::array<std::uint64_t, kMaxPasses> digit_mask{};
  for (int p = 0; p < passes; ++p) {
    const int bits = std::min(kRadixDigitBits, key_bits - p * kRadixDigitBits);
    digit_mask[p] = (std::uint64_t{1} << bits) - 1;
  }
  std::array<std::array<std::uint32_t, kBuckets>, kMaxPasses> counts{};
  for (const Record& r : data) {
    for (int p = 0; p < passes; ++p) {
      ++counts[p][(key_of(r) >> (first_bit + p * kRadixDigitBits)) & digit_mask[p]];
    }
  }
  scratch.resize(n);
  for (int p = 0; p < passes; ++p) {
    std::array<std::uint32_t, kBuckets>& offset = counts[p];
    const int shift = first_bit + p * kRadixDigitBits;
    const std::uint64_t mask = digit_mask[p];
    if (offset[(key_of(data[0]) >> shift) & mask] == n) continue;  // one digit value: nothing moves
    std::uint32_t sum = 0;
    for (std::uint32_t& c : offset) sum += std::exchange(c, sum);
    for (const Record& r : data) scratch[offset[(key_of(r) >> shift) & mask]++] = r;
    data.swap(scratch);
  }
}

/// Sorts `data` by bits [first_bit, first_bit + key_bits) of `record.key`, stably (radix_sort).
template <class Record>
void radix_sort_by_key(std::vector<Record>& data, std::vector<Record>& scratch, int first_bit,
                       int key_bits) {
  radix_sort(data, scratch, first_bit, key_bits, [](const Record& r) { return r.key; });
}

/// One edge use of a triangle list: use number 3 t + k is the edge from corner k to corner
/// k + 1 of triangle t; `key` orders the unordered pair of its end vertices.
struct EdgeUse {
  std::uint64_t key;
  std::uint64_t use;  ///< 64 bits: three uses a triangle overflow 32 bits past 1.4e9 triangles
};

/// The edge uses of `triangles` sorted by the unordered pair of their end vertices, uses of one
/// pair in ascending number: each run of equal keys is an edge and the triangles that share it
/// (a run of one: a boundary edge). `vertex_of(index)` maps a corner's vertex index to the id
/// the pairs are made of (ids below `vertex_count`; the identity, or a weld's representative).
/// Radix sorted (stable) as one 64-bit word a use, the pair above the use number, when both fit
/// (half the bytes of records to move), else as records. Shared by TriangleMesh's active edges
/// and the walk mesh build's T-junction pass (std::sort was a sixth and a tenth of them).
/// Allocates the result and its scratch; reports no errors.
template <class VertexOf>
[[nodiscard]] std::vector<EdgeUse> sort_edge_uses(std::span<const glm::uvec3> triangles, std::size_t vertex_count,
                                                  VertexOf&& vertex_of) {
  const int half = static_cast<int>(std::bit_width(std::max<std::size_t>(vertex_count, 2) - 1));  // at most 32
  const std::size_t count = 3 * triangles.size();
  const int use_bits = static_cast<int>(std::bit_width(std::max<std::size_t>(count, 2) - 1));
  auto key_of = [&](std::size_t use) {
    const glm::uvec3& t = triangles[use / 3];
    const int k = static_cast<int>(use % 3);
    const std::uint64_t u = vertex_of(t[k]), v = vertex_of(t[(k + 1) % 3]);
    return std::min(u, v) << half | std::max(u, v);
  };
  std::vector<EdgeUse> uses(count);
  if (2 * half + use_bits <= 64) {
    std::vector<std::uint64_t> packed(count), scratch;
    for (std::size_t i = 0; i < count; ++i) packed[i] = key_of(i) << use_bits | i;
    radix_sort(packed, scratch, use_bits, 2 * half, [](std::uint64_t p) { return p; });
    const std::uint64_t mask = (std::uint64_t{1} << use_bits) - 1;
    for (std::size_t i = 0; i < count; ++i) uses[i] = {packed[i] >> use_bits, packed[i] & mask};
  } else {
    std::vector<EdgeUse> scratch;
    for (std::size_t i = 0; i < count; ++i) uses[i] = {key_of(i), i};
    radix_sort_by_key(uses, scratch, 0, 2 * half);
  }
  return uses;
}

}  // namespace collide
