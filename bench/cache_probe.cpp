// cache_probe: how much data one core finds in cache on this machine, measured rather
// than read from /sys (bench/README.md, session 20).
//
// For each working-set size it chases a pointer through one 8-byte word in every 64-byte
// line of the set, in one random cyclic order, so each load waits for the one before and
// no prefetcher can guess the next line. The time per load is the latency of wherever
// the set lives: a few ns in L1 and L2, ~10–15 ns in the last-level cache, ~100 ns and
// more in DRAM. The size where it jumps is the cache this process gets, which on a
// shared virtual machine can be far smaller than the size the kernel reports for the
// processor's last-level cache.
//
// Two columns: the set in 4 KiB pages (as cdm's arrays are), and the same set advised
// into transparent huge pages (madvise MADV_HUGEPAGE), which takes the page walks out of
// the measure: where both columns jump at the same size, the cache, not the TLB, is
// what ran out.
//
//   cache_probe [--loads=N] [SIZE_MiB ...]
//
// prints "MiB ns_4k ns_huge" per size (default sizes 0.5 1 2 4 6 8 12 16 24 32 64 256;
// N = 4e6 dependent loads per measure, after one warm lap of the set).
#include <sys/mman.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr std::size_t kLine = 64;
constexpr std::size_t kHuge = std::size_t{2} << 20;

bool parse_positive(const char* s, double& out) {
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  if (end == s || *end != '\0' || !(v > 0.0)) return false;
  out = v;
  return true;
}

// ns per dependent load over a set of @p bytes, huge pages advised if @p huge.
double chase(std::size_t bytes, bool huge, std::size_t loads) {
  const std::size_t lines = std::max<std::size_t>(2, bytes / kLine);
  const std::size_t size = (lines * kLine + kHuge - 1) / kHuge * kHuge;
  void* mem = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (mem == MAP_FAILED) {
    std::fprintf(stderr, "cache_probe: cannot map %zu bytes\n", size);
    std::exit(1);
  }
  madvise(mem, size, huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
  auto* words = static_cast<std::uint64_t*>(mem);
  constexpr std::size_t stride = kLine / sizeof(std::uint64_t);
  std::vector<std::uint64_t> order(lines);
  std::iota(order.begin(), order.end(), std::uint64_t{0});
  std::shuffle(order.begin(), order.end(), std::mt19937_64(20261124));
  for (std::size_t k = 0; k < lines; ++k) words[order[k] * stride] = order[(k + 1) % lines] * stride;
  std::uint64_t at = 0;
  for (std::size_t k = 0; k < lines; ++k) at = words[at];  // one warm lap
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < loads; ++k) at = words[at];
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
  // The chain's end, kept observable so the loop is not removed.
  if (at == ~std::uint64_t{0}) std::puts("");
  munmap(mem, size);
  return ns / static_cast<double>(loads);
}

}  // namespace

int main(int argc, char** argv) {
  double loads = 4e6;
  std::vector<double> sizes;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    double v = 0.0;
    if (arg.rfind("--loads=", 0) == 0) {
      if (!parse_positive(argv[a] + 8, v) || v < 1.0 || v > 1e10) {
        std::fprintf(stderr, "cache_probe: --loads: expected a count from 1 to 1e10, got '%s'\n", argv[a] + 8);
        return 2;
      }
      loads = v;
    } else if (parse_positive(argv[a], v) && v <= 65536.0) {
      sizes.push_back(v);
    } else {
      std::fprintf(stderr, "cache_probe: expected a working-set size in MiB (0 < size <= 65536) or --loads=N, got '%s'\n",
                   argv[a]);
      return 2;
    }
  }
  if (sizes.empty()) sizes = {0.5, 1, 2, 4, 6, 8, 12, 16, 24, 32, 64, 256};
  std::printf("# MiB ns_4k ns_huge: ns per dependent load over a working set of MiB, 4 KiB pages / huge pages advised\n");
  for (const double mib : sizes) {
    const auto bytes = static_cast<std::size_t>(mib * 1024.0 * 1024.0);
    const auto n = static_cast<std::size_t>(loads);
    const double small = chase(bytes, false, n);
    const double huge = chase(bytes, true, n);
    std::printf("%g %.1f %.1f\n", mib, small, huge);
  }
  return 0;
}
