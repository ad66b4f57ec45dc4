#pragma once
/// @file
/// Least-significant-digit radix sort of records by an unsigned 64-bit key: stable,
/// O(n) per 11-bit digit, one read pass for all digit histograms, and passes whose digit is the
/// same for every record skipped. (Knuth, TAOCP vol. 3, 5.2.5.) Shared by the broad phases'
/// pair lists and grids and the walk mesh build's edge list; in `detail`: not part of the API
/// a game uses.

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace collide::detail {

inline constexpr int kRadixDigitBits = 11;

/// Sorts `data` by bits [first_bit, first_bit + key_bits) of `key_of(record)` (an unsigned
/// 64-bit value); `scratch` is reused storage.
template <class Record, class KeyOf>
void radix_sort(std::vector<Record>& data, std::vector<Record>& scratch, int first_bit, int key_bits,
                KeyOf&& key_of) {
  constexpr std::size_t kBuckets = std::size_t{1} << kRadixDigitBits;
  constexpr std::uint64_t kMask = kBuckets - 1;
  constexpr int kMaxPasses = (64 + kRadixDigitBits - 1) / kRadixDigitBits;
  const int passes = (key_bits + kRadixDigitBits - 1) / kRadixDigitBits;
  const std::size_t n = data.size();
  if (passes == 0 || n < 2) return;

  std::array<std::array<std::uint32_t, kBuckets>, kMaxPasses> counts{};
  for (const Record& r : data) {
    for (int p = 0; p < passes; ++p) {
      ++counts[p][(key_of(r) >> (first_bit + p * kRadixDigitBits)) & kMask];
    }
  }
  scratch.resize(n);
  for (int p = 0; p < passes; ++p) {
    std::array<std::uint32_t, kBuckets>& offset = counts[p];
    const int shift = first_bit + p * kRadixDigitBits;
    if (offset[(key_of(data[0]) >> shift) & kMask] == n) continue;  // one digit value: nothing moves
    std::uint32_t sum = 0;
    for (std::uint32_t& c : offset) sum += std::exchange(c, sum);
    for (const Record& r : data) scratch[offset[(key_of(r) >> shift) & kMask]++] = r;
    data.swap(scratch);
  }
}

/// Sorts `data` by bits [first_bit, first_bit + key_bits) of `record.key`.
template <class Record>
void radix_sort_by_key(std::vector<Record>& data, std::vector<Record>& scratch, int first_bit,
                       int key_bits) {
  radix_sort(data, scratch, first_bit, key_bits, [](const Record& r) { return r.key; });
}

}  // namespace collide::detail
