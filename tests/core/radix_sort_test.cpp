// radix_sort and sort_edge_uses (core/radix_sort.hpp) against independent answers: std::stable_sort
// on the same bits, and edge uses grouped by brute force (every pair of uses compared).

#include <collide/core/radix_sort.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <utility>
#include <vector>

namespace collide {
namespace {

struct Keyed {
  std::uint64_t key;
  int tag;  // the record's position before sorting: stability shows in it
};

// Records sorted by a bit range of their keys, against std::stable_sort by the same bits: the
// same order record for record (equal bits keep their input order), for ranges of one pass,
// several, a range not starting at bit 0, and one reaching bit 63.
TEST(RadixSort, MatchesStableSortOnTheSameBits) {
  std::mt19937_64 rng(11);
  const std::pair<int, int> ranges[] = {{0, 8}, {0, 30}, {5, 17}, {20, 44}, {0, 64}, {40, 24}};
  for (const auto& [first_bit, key_bits] : ranges) {
    for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{5000}}) {
      std::vector<Keyed> data(n);
      for (std::size_t i = 0; i < n; ++i) {
        // Few distinct values in the range, so that ties are common.
        data[i] = {rng() & ~(((std::uint64_t{1} << 4) - 1) << (first_bit + 2 < 60 ? first_bit + 2 : 0)),
                   static_cast<int>(i)};
        if (i % 3 == 0 && i > 0) data[i].key = data[i - 1].key;
      }
      const std::uint64_t mask =
          key_bits == 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << key_bits) - 1) << first_bit;
      std::vector<Keyed> expected = data;
      std::stable_sort(expected.begin(), expected.end(),
                       [mask](const Keyed& a, const Keyed& b) { return (a.key & mask) < (b.key & mask); });
      std::vector<Keyed> scratch;
      radix_sort_by_key(data, scratch, first_bit, key_bits);
      ASSERT_EQ(data.size(), expected.size());
      for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(data[i].tag, expected[i].tag) << "bits " << first_bit << "+" << key_bits << ", n " << n << ", i " << i;
      }
    }
  }
}

// Edge uses of a random triangle list (repeated vertices, shared and unshared edges, a few
// triangles through one edge, a weld map merging vertex ids): sorted by their unordered pair,
// ties in use order, and every run of equal keys is exactly the uses brute force finds on that
// pair.
TEST(SortEdgeUses, GroupsEveryUseOfAPairInUseOrder) {
  std::mt19937 rng(5);
  for (const std::uint32_t vertices : {3u, 12u, 70000u}) {
    std::vector<glm::uvec3> triangles;
    std::uniform_int_distribution<std::uint32_t> pick(0, vertices - 1);
    for (int t = 0; t < 3000; ++t) {
      glm::uvec3 tri{pick(rng), pick(rng), pick(rng)};
      if (t % 5 == 1 && !triangles.empty()) tri.x = triangles.back().y, tri.y = triangles.back().x;  // shares an edge
      triangles.push_back(tri);
    }
    // A weld: ids folded onto fewer representatives.
    std::vector<std::uint32_t> rep(vertices);
    for (std::uint32_t v = 0; v < vertices; ++v) rep[v] = v % 2 == 0 || vertices < 4 ? v : v - 1;
    const std::vector<EdgeUse> uses = sort_edge_uses(triangles, vertices, [&](std::uint32_t v) { return rep[v]; });
    ASSERT_EQ(uses.size(), 3 * triangles.size());

    auto pair_of = [&](std::uint64_t use) {
      const glm::uvec3& t = triangles[use / 3];
      const int k = static_cast<int>(use % 3);
      const std::uint32_t a = rep[t[k]], b = rep[t[(k + 1) % 3]];
      return std::make_pair(std::min(a, b), std::max(a, b));
    };
    // Brute force: the uses of each pair, in use order.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint64_t>> expected;
    for (std::uint64_t u = 0; u < uses.size(); ++u) expected[pair_of(u)].push_back(u);

    std::size_t i = 0;
    for (const auto& [pair, list] : expected) {  // std::map: pairs in ascending order
      ASSERT_LT(i, uses.size());
      const std::uint64_t run_key = uses[i].key;  // every use of the pair carries one key
      for (const std::uint64_t u : list) {
        ASSERT_LT(i, uses.size());
        EXPECT_EQ(uses[i].use, u) << "vertices " << vertices << ", position " << i;
        EXPECT_EQ(uses[i].key, run_key) << "vertices " << vertices << ", position " << i;
        ++i;
      }
      // The run ends where the pair does.
      if (i < uses.size()) EXPECT_NE(uses[i].key, uses[i - 1].key) << "vertices " << vertices;
    }
    EXPECT_EQ(i, uses.size());
  }
}

}  // namespace
}  // namespace collide
