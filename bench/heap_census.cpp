// heap_census: what a process holds resident at its peak, allocation by allocation.
//
// A library preloaded into a run (LD_PRELOAD=libheap_census.so), not linked into cdm. It
// records every allocation of at least CDM_CENSUS_MIN bytes (default 65536) with its call
// stack; whenever the process's resident memory (/proc/self/statm) passes its highest so
// far by a MiB, it writes every live recorded allocation with its size and its resident
// bytes (mincore) to $CDM_CENSUS_DIR/census.R (R: OMPI_COMM_WORLD_RANK, or 0), replacing
// the last. The file then describes the moment of the peak as seen at the allocation that
// reached it. Beside it, census.R.freed gives the resident pages no live allocation holds
// (what the allocator kept), each by the latest of the last 4096 recorded allocations freed
// whose range held it. Each frame is written as an offset into its object file, so that
// heap_census.py can name it with addr2line. The census's own table (7 MB of address
// space) adds a page per live record to the resident memory it reports. bench/README.md,
// "What stays resident between builds".
#include <dlfcn.h>
#include <execinfo.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace {

constexpr std::size_t kSlots = std::size_t{1} << 16;  // live allocations recorded at once
constexpr int kFrames = 10;
void* const kGone = reinterpret_cast<void*>(1);  // a freed slot (open addressing)

struct Record {
  void* p = nullptr;
  std::size_t bytes = 0;
  int frames = 0;
  void* frame[kFrames];
};

Record* table = nullptr;  // kSlots records, mapped at start
constexpr std::size_t kFreed = 4096;  // the latest freed allocations, newest last
Record* freed = nullptr;              // kFreed records, mapped at start
std::size_t freed_count = 0;          // how many were ever freed (ring index: % kFreed)
constexpr std::size_t kMapPages = std::size_t{1} << 22;  // the pages a census can tell apart
unsigned char* claimed = nullptr;                        // a bit a page, mapped at start
std::mutex table_mutex;
thread_local bool in_hook = false;

using MallocFn = void* (*)(std::size_t);
using FreeFn = void (*)(void*);
using ReallocFn = void* (*)(void*, std::size_t);
using CallocFn = void* (*)(std::size_t, std::size_t);
MallocFn real_malloc = nullptr;
FreeFn real_free = nullptr;
ReallocFn real_realloc = nullptr;
CallocFn real_calloc = nullptr;

// dlsym may call calloc before real_calloc is known: such calls get this memory.
alignas(16) char bootstrap[1 << 16];
std::atomic<std::size_t> bootstrap_used{0};

std::size_t min_bytes = 65536;
long page = 4096;
long peak_pages = 0;
char out_path[4096] = "";

std::size_t slot_of(const void* p) {
  return static_cast<std::size_t>((reinterpret_cast<std::uintptr_t>(p) >> 4) * 0x9E3779B97F4A7C15ull >> 44) &
         (kSlots - 1);
}

long resident_pages() {
  const int fd = open("/proc/self/statm", O_RDONLY);
  if (fd < 0) return 0;
  char buf[128];
  const ssize_t n = read(fd, buf, sizeof buf - 1);
  close(fd);
  if (n <= 0) return 0;
  buf[n] = 0;
  long size = 0, rss = 0;
  return std::sscanf(buf, "%ld %ld", &size, &rss) == 2 ? rss : 0;
}

// One line: BYTES RESIDENT FRAME... (frames as offsets into their object files).
bool write_record(int fd, const Record& r, std::size_t resident) {
  char line[8192];
  int n = std::snprintf(line, sizeof line, "%zu %zu", r.bytes, resident);
  for (int f = 0; f < r.frames && n < 7000; ++f) {
    Dl_info info;
    if (dladdr(r.frame[f], &info) && info.dli_fname)
      n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), " %lx@%s",
                         static_cast<unsigned long>(reinterpret_cast<std::uintptr_t>(r.frame[f]) -
                                                    reinterpret_cast<std::uintptr_t>(info.dli_fbase)),
                         info.dli_fname);
  }
  line[n++] = '\n';
  return write(fd, line, static_cast<std::size_t>(n)) == n;
}

// The bytes of the resident pages wholly inside [p, p + bytes). With @p claim, only those
// not claimed yet, each claimed now (pages beyond the map's span from @p base are counted
// without a claim).
std::size_t resident_bytes(const void* p, std::size_t bytes, bool claim = false, std::uintptr_t base = 0) {
  const auto a = (reinterpret_cast<std::uintptr_t>(p) + page - 1) / page * page;
  const auto b = (reinterpret_cast<std::uintptr_t>(p) + bytes) / page * page;
  std::size_t pages = 0;
  unsigned char vec[4096];
  for (std::uintptr_t s = a; s < b;) {
    const std::uintptr_t len = std::min<std::uintptr_t>(b - s, sizeof vec * page);
    if (mincore(reinterpret_cast<void*>(s), len, vec) == 0)
      for (std::uintptr_t k = 0; k < len / page; ++k) {
        if (!(vec[k] & 1)) continue;
        if (!claim) { ++pages; continue; }
        const std::uintptr_t at = (s - base) / page + k;
        if (s < base || at >= kMapPages) { ++pages; continue; }
        unsigned char& byte = claimed[at / 8];
        const unsigned char bit = static_cast<unsigned char>(1u << (at % 8));
        if (byte & bit) continue;
        byte |= bit;
        ++pages;
      }
    s += len;
  }
  return pages * static_cast<std::size_t>(page);
}

// A census file, out_path + @p suffix, written under a temporary name and renamed once
// whole: open() writes its first line ("rss BYTES") and says whether all went well.
struct CensusFile {
  char path[4200], tmp[4205];
  int fd = -1;
  bool open(const char* suffix, long rss_pages) {
    std::snprintf(path, sizeof path, "%s%s", out_path, suffix);
    std::snprintf(tmp, sizeof tmp, "%s.tmp", path);
    fd = ::open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) return false;
    char line[64];
    const int n = std::snprintf(line, sizeof line, "rss %ld\n", rss_pages * page);
    return write(fd, line, static_cast<std::size_t>(n)) == n;
  }
  void close(bool ok) {
    if (fd < 0) return;
    ::close(fd);
    if (ok) rename(tmp, path);
  }
};

// The census's second file (out_path.freed): the resident pages that no live allocation
// holds, by the latest freed allocation whose range held them (newest first), in
// write_census's format: what the allocator kept of whom.
void write_freed(long rss_pages) {
  if (freed == nullptr || claimed == nullptr) return;
  std::uintptr_t base = ~std::uintptr_t{0};
  for (std::size_t s = 0; s < kSlots; ++s)
    if (table[s].p != nullptr && table[s].p != kGone)
      base = std::min(base, reinterpret_cast<std::uintptr_t>(table[s].p));
  for (std::size_t k = 0; k < std::min(freed_count, kFreed); ++k)
    base = std::min(base, reinterpret_cast<std::uintptr_t>(freed[k].p));
  base = base / page * page;
  std::memset(claimed, 0, kMapPages / 8);
  for (std::size_t s = 0; s < kSlots; ++s)
    if (table[s].p != nullptr && table[s].p != kGone) resident_bytes(table[s].p, table[s].bytes, true, base);
  CensusFile f;
  bool ok = f.open(".freed", rss_pages);
  for (std::size_t k = 0; ok && k < std::min(freed_count, kFreed); ++k) {
    const Record& r = freed[(freed_count - 1 - k) % kFreed];
    const std::size_t resident = resident_bytes(r.p, r.bytes, true, base);
    if (resident > 0) ok = write_record(f.fd, r, resident);
  }
  f.close(ok);
}

// Writes the census (table_mutex held). No allocation: snprintf into a stack buffer.
void write_census(long rss_pages) {
  CensusFile f;
  bool ok = f.open("", rss_pages);
  for (std::size_t s = 0; ok && s < kSlots; ++s) {
    const Record& r = table[s];
    if (r.p == nullptr || r.p == kGone) continue;
    ok = write_record(f.fd, r, resident_bytes(r.p, r.bytes));
  }
  f.close(ok);
  write_freed(rss_pages);
}

void record(void* p, std::size_t bytes) {
  if (p == nullptr || bytes < min_bytes || in_hook || table == nullptr) return;
  in_hook = true;
  {
    std::lock_guard<std::mutex> lock(table_mutex);
    for (std::size_t s = slot_of(p), k = 0; k < kSlots; ++k, s = (s + 1) & (kSlots - 1)) {
      Record& r = table[s];
      if (r.p != nullptr && r.p != kGone) continue;
      r.p = p;
      r.bytes = bytes;
      r.frames = backtrace(r.frame, kFrames);
      break;
    }
    const long rss = resident_pages();
    if (rss > peak_pages + (1 << 20) / page) {
      peak_pages = rss;
      write_census(rss);
    }
  }
  in_hook = false;
}

void forget(void* p) {
  if (p == nullptr || table == nullptr || in_hook) return;
  std::lock_guard<std::mutex> lock(table_mutex);
  for (std::size_t s = slot_of(p), k = 0; k < kSlots && table[s].p != nullptr; ++k, s = (s + 1) & (kSlots - 1))
    if (table[s].p == p) {
      if (freed != nullptr) freed[freed_count++ % kFreed] = table[s];
      table[s].p = kGone;
      return;
    }
}

bool from_bootstrap(const void* p) {
  return p >= static_cast<const void*>(bootstrap) && p < static_cast<const void*>(bootstrap + sizeof bootstrap);
}

void resolve() {
  if (real_malloc) return;
  real_calloc = reinterpret_cast<CallocFn>(dlsym(RTLD_NEXT, "calloc"));
  real_free = reinterpret_cast<FreeFn>(dlsym(RTLD_NEXT, "free"));
  real_realloc = reinterpret_cast<ReallocFn>(dlsym(RTLD_NEXT, "realloc"));
  real_malloc = reinterpret_cast<MallocFn>(dlsym(RTLD_NEXT, "malloc"));
}

__attribute__((constructor)) void start() {
  resolve();
  page = sysconf(_SC_PAGESIZE);
  if (const char* m = std::getenv("CDM_CENSUS_MIN")) min_bytes = std::strtoull(m, nullptr, 10);
  const char* dir = std::getenv("CDM_CENSUS_DIR");
  const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
  std::snprintf(out_path, sizeof out_path, "%s/census.%s", dir ? dir : ".", rank ? rank : "0");
  void* frames[2];
  in_hook = true;
  backtrace(frames, 2);  // loads the unwinder now, not inside a hook
  in_hook = false;
  void* t = mmap(nullptr, kSlots * sizeof(Record), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (t != MAP_FAILED) table = static_cast<Record*>(t);
  void* f = mmap(nullptr, kFreed * sizeof(Record), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (f != MAP_FAILED) freed = static_cast<Record*>(f);
  void* c = mmap(nullptr, kMapPages / 8, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (c != MAP_FAILED) claimed = static_cast<unsigned char*>(c);
}

}  // namespace

extern "C" {

void* malloc(std::size_t n) {
  resolve();
  void* p = real_malloc(n);
  record(p, n);
  return p;
}

void* calloc(std::size_t count, std::size_t size) {
  if (!real_calloc) {  // inside dlsym, before the real one is known
    const std::size_t bytes = (count * size + 15) / 16 * 16;
    const std::size_t at = bootstrap_used.fetch_add(bytes);
    if (at + bytes > sizeof bootstrap) return nullptr;
    return bootstrap + at;  // static storage: already zero
  }
  void* p = real_calloc(count, size);
  record(p, count * size);
  return p;
}

void* realloc(void* q, std::size_t n) {
  resolve();
  forget(q);
  void* p = real_realloc(q, n);
  record(p, n);
  return p;
}

void free(void* p) {
  if (from_bootstrap(p)) return;
  resolve();
  forget(p);
  real_free(p);
}

}  // extern "C"
