#pragma once
// The instruction sets of a benchmark's two sides, for its context block (printed before the
// results and stored in --benchmark_out JSON): collide's, read from the compiler's predefined
// macros of the benchmark's own source (built with the same flags as the library, unless a
// target says otherwise by COLLIDE_BENCH_ISA), and a peer's as the peer reports it.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
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

/// Picoseconds per operation of a wide loop of independent register operations (two shuffles,
/// two address computations, a move and an add per group: up to six a cycle), the fastest of
/// five runs of about 2 ms (an interruption slows one run, a shared core all five): how much of
/// the core's dispatch width this thread gets. On the project's 2-vCPU AMD VM (a Zen 3 core) it
/// reads 52-56 ps most of the time and 70-85 in stretches of minutes when collide's branch-free
/// SIMD queries run 30-70% slower and the rivals' branchy code 5-15%: another hardware thread
/// busy on the host's core (SMT), sharing the dispatch slots; FP multiplies at two a cycle, L1
/// and L2 load latency and the divider's throughput stay within 10% there (stop 81,
/// docs/performance.md). A figure to read ratios by, not a correction. 0 where it cannot run
/// (not x86-64 with GCC or Clang). `runs` (1 to 5) trades the figure's noise for time: a
/// benchmark that probes between its own timed blocks takes one run.
inline double host_dispatch_probe_ps(int runs = 5) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// One group: six operations that read only registers nothing in the loop writes.
#define COLLIDE_PROBE_GROUP(from_a, from_b, to_a, to_b)                                     \
  "pshufd $0x1b, %%xmm" from_a ", %%xmm" to_a "\n\t"                                       \
  "pshufd $0x4e, %%xmm" from_b ", %%xmm" to_b "\n\t"                                       \
  "lea 8(%%rsi,%%rdi), %%r8\n\t"                                                           \
  "lea 16(%%rdi,%%rsi), %%r9\n\t"                                                          \
  "mov %%rsi, %%r10\n\t"                                                                   \
  "add $1, %%r11\n\t"
#define COLLIDE_PROBE_FOUR                                                                  \
  COLLIDE_PROBE_GROUP("0", "1", "8", "9") COLLIDE_PROBE_GROUP("2", "3", "10", "11")        \
  COLLIDE_PROBE_GROUP("4", "5", "12", "13") COLLIDE_PROBE_GROUP("6", "7", "14", "15")
  constexpr long kLoops = 400000;  // 96 operations a loop: 38.4M a run, about 2 ms
  double times[5];
  const int count = std::clamp(runs, 1, 5);
  for (int r = 0; r < count; ++r) {
    double& run = times[r];
    const auto start = std::chrono::steady_clock::now();
    for (long i = 0; i < kLoops; ++i) {
      asm volatile(COLLIDE_PROBE_FOUR COLLIDE_PROBE_FOUR COLLIDE_PROBE_FOUR COLLIDE_PROBE_FOUR::
                       : "xmm8", "xmm9", "xmm10", "xmm11", "xmm12", "xmm13", "xmm14", "xmm15", "r8", "r9",
                         "r10", "r11");
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run = seconds * 1e12 / (static_cast<double>(kLoops) * 96.0);
  }
#undef COLLIDE_PROBE_FOUR
#undef COLLIDE_PROBE_GROUP
  return *std::min_element(times, times + count);
#else
  static_cast<void>(runs);
  return 0.0;
#endif
}

/// host_dispatch_probe_ps as a context line: the figure and how to read it.
inline std::string host_dispatch_probe_text() {
  const double ps = host_dispatch_probe_ps();
  if (!(ps > 0.0)) return "not measured (x86-64 only)";
  char text[200];
  std::snprintf(text, sizeof text,
                "%.1f ps an operation (project's Zen 3 VM: 52-56 with its core to itself, 70-85 when "
                "another hardware thread shares it: then collide's rows read slower; its Zen 5 "
                "host: 39-47)",
                ps);
  return text;
}

/// Instruction set of a peer from Debian's x86-64 packages (built for the x86-64 baseline).
inline constexpr const char* kDebianPackageIsa = "SSE2 (Debian's x86-64 package)";

/// Adds collide's instruction set, the host processor and the host dispatch probe to the
/// benchmark context (once per run), after benchmark::Initialize; the probe again at exit.
inline void add_collide_context() {
  static const bool added = [] {
    benchmark::AddCustomContext("collide instruction set", compiled_instruction_set());
    benchmark::AddCustomContext("host processor", host_processor());
    benchmark::AddCustomContext("host dispatch probe at start", host_dispatch_probe_text());
    // Again as the process ends, after the rows (the context block is printed before them), on
    // stderr: a run whose two probes differ crossed a change in the core's sharing.
    std::atexit([] { std::fprintf(stderr, "host dispatch probe at end: %s\n", host_dispatch_probe_text().c_str()); });
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
