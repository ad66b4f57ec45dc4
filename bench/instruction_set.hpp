#pragma once
// The instruction sets of a benchmark's two sides, for its context block (printed before the
// results and stored in --benchmark_out JSON): collide's, read from the compiler's predefined
// macros of the benchmark's own source (built with the same flags as the library, unless a
// target says otherwise by COLLIDE_BENCH_ISA), and a peer's as the peer reports it.

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <string>

#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
#define COLLIDE_BENCH_HAS_CPUID 1
#endif

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

/// The processor the benchmark runs on, from CPUID: brand, vendor, family, model and stepping
/// (as the vendors' manuals number them, in hex), L2 size per core and whether it has AVX-512
/// (which x86 generations differ by). A VM's brand can be as bare as "AMD EPYC", so runs on
/// hosts of different generations read alike without these numbers (the project's AMD VM, in
/// the slow phase of its benchmarks on 2026-12-02: family 19h model 01h, a Zen 3 core).
inline std::string host_processor() {
#ifdef COLLIDE_BENCH_HAS_CPUID
  unsigned a = 0, b = 0, c = 0, d = 0;
  if (__get_cpuid(0, &a, &b, &c, &d) == 0) return "unknown (no CPUID)";
  const unsigned max_leaf = a;
  char vendor[13] = {};
  std::memcpy(vendor, &b, 4);
  std::memcpy(vendor + 4, &d, 4);
  std::memcpy(vendor + 8, &c, 4);
  __get_cpuid(1, &a, &b, &c, &d);
  const unsigned base_family = (a >> 8) & 0xFu;
  const unsigned family = base_family == 0xFu ? base_family + ((a >> 20) & 0xFFu) : base_family;
  const unsigned model = (base_family == 0x6u || base_family == 0xFu)
                             ? (((a >> 16) & 0xFu) << 4) | ((a >> 4) & 0xFu)
                             : (a >> 4) & 0xFu;
  const unsigned stepping = a & 0xFu;
  bool avx512 = false;
  if (max_leaf >= 7) {
    __cpuid_count(7, 0, a, b, c, d);
    avx512 = ((b >> 16) & 1u) != 0;
  }
  char brand[49] = {};
  unsigned l2_kib = 0;
  if (__get_cpuid(0x80000000u, &a, &b, &c, &d) != 0) {
    const unsigned max_extended = a;
    if (max_extended >= 0x80000004u) {
      for (unsigned i = 0; i < 3; ++i) {
        __get_cpuid(0x80000002u + i, &a, &b, &c, &d);
        std::memcpy(brand + 16 * i, &a, 4);
        std::memcpy(brand + 16 * i + 4, &b, 4);
        std::memcpy(brand + 16 * i + 8, &c, 4);
        std::memcpy(brand + 16 * i + 12, &d, 4);
      }
    }
    if (max_extended >= 0x80000006u) {
      __get_cpuid(0x80000006u, &a, &b, &c, &d);
      l2_kib = c >> 16;
    }
  }
  std::string name = brand;
  while (!name.empty() && name.front() == ' ') name.erase(name.begin());
  while (!name.empty() && name.back() == ' ') name.pop_back();
  char text[160];
  std::snprintf(text, sizeof text, "%s (%s family %02Xh model %02Xh stepping %u; L2 %u KiB; AVX-512 %s)",
                name.empty() ? "unnamed" : name.c_str(), vendor, family, model, stepping, l2_kib,
                avx512 ? "yes" : "no");
  return text;
#else
  return "unknown (not x86)";
#endif
}

/// Instruction set of a peer from Debian's x86-64 packages (built for the x86-64 baseline).
inline constexpr const char* kDebianPackageIsa = "SSE2 (Debian's x86-64 package)";

/// Adds collide's instruction set and the host processor to the benchmark context (once per
/// run), after benchmark::Initialize.
inline void add_collide_context() {
  static const bool added = [] {
    benchmark::AddCustomContext("collide instruction set", compiled_instruction_set());
    benchmark::AddCustomContext("host processor", host_processor());
    return true;
  }();
  static_cast<void>(added);
}

/// Adds collide's context (add_collide_context) and `peer` with its instruction set to the
/// benchmark context; call once per peer, after benchmark::Initialize.
inline void add_instruction_sets(const std::string& peer, const std::string& peer_isa) {
  add_collide_context();
  benchmark::AddCustomContext(peer + " instruction set", peer_isa);
}

/// A benchmark binary's main: benchmark::Initialize (unknown flags rejected), then
/// `add_context()` (the run's context block: instruction sets, versions), then every benchmark
/// the flags select. Returns the process's exit status.
template <class AddContext>
int run_benchmarks(int argc, char** argv, AddContext add_context) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  add_context();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace collide::bench
