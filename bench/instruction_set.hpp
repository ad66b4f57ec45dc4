#pragma once
// The instruction sets of a benchmark's two sides, for its context block (printed before the
// results and stored in --benchmark_out JSON): collide's, read from the compiler's predefined
// macros of the benchmark's own source (built with the same flags as the library, unless a
// target says otherwise by COLLIDE_BENCH_ISA), and a peer's as the peer reports it.

#include <benchmark/benchmark.h>

#include <string>

namespace collide::bench {

/// The x86 extensions this source was compiled for, e.g. "SSE2" or "SSE2 SSE4.1 ... AVX2 FMA".
inline std::string compiled_instruction_set() {
#ifdef COLLIDE_BENCH_ISA
  return COLLIDE_BENCH_ISA;
#else
  std::string s;
  const auto add = [&s](const char* name) { s += s.empty() ? name : std::string(" ") + name; };
#ifdef __SSE2__
  add("SSE2");
#endif
#ifdef __SSE4_1__
  add("SSE4.1");
#endif
#ifdef __SSE4_2__
  add("SSE4.2");
#endif
#ifdef __AVX__
  add("AVX");
#endif
#ifdef __AVX2__
  add("AVX2");
#endif
#ifdef __FMA__
  add("FMA");
#endif
#ifdef __AVX512F__
  add("AVX512F");
#endif
  if (s == "SSE2") s += " (the x86-64 baseline, collide's default build)";
  return s.empty() ? "unknown" : s;
#endif
}

/// Adds "collide" (once per run) and `peer` with their instruction sets to the benchmark
/// context; call once per peer, after benchmark::Initialize.
inline void add_instruction_sets(const std::string& peer, const std::string& peer_isa) {
  static const bool collide_added = [] {
    benchmark::AddCustomContext("collide instruction set", compiled_instruction_set());
    return true;
  }();
  static_cast<void>(collide_added);
  benchmark::AddCustomContext(peer + " instruction set", peer_isa);
}

}  // namespace collide::bench
