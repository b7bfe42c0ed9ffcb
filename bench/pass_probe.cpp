// pass_probe: the memory traffic of velocity Verlet's one pass per step, without cdm,
// in four memory layouts and two ways of sweeping one of them, and three variants of the
// traffic for a bed of one kind of particle.
//
// The pass (verlet_pass, solver/src/integrators/verlet_kernels.hpp) reads and rewrites
// 15 doubles per particle (position, half-step velocity, force, half-step spin, torque), reads 3
// (mass, inverse mass, inverse inertia) and writes 6 it does not read (predicted
// velocity and spin, whose lines the processor still reads for ownership): 360 bytes
// per particle-step between the core and wherever the data lives. This program sweeps
// the same 24 doubles per particle with the same reads and writes and next to no
// arithmetic, so that cdm's pass time per particle can be set against what the memory
// system gives one core for that traffic at that N (issue #7: cost per particle-step
// at 1e6 against 1e4), and against what another layout would give:
//
//   soa       24 arrays, one per quantity, their starts 16 bytes apart modulo the
//             4 KiB page (as cdm's heap-allocated ParticleStore arrays mostly are)
//   soa-axis  the soa arrays, swept as cdm's pass now sweeps them: one axis at a time
//             (x, then y, then z of position, velocities and force; then each axis of
//             the spins and torque) over blocks of 32768 particles, 4 to 6 arrays a loop
//   soa-axis-2k  the same over blocks of 2048 particles (cdm's pass in sessions 13–15):
//             each loop starts its streams 16 times as often
//   soa-page  the same 24 arrays all starting at the same offset in a page (as arrays
//             allocated separately by mmap are): every array maps to the same cache
//             sets, a hazard for any structure-of-arrays code
//   vec3      8 arrays of 3 interleaved doubles (x y z, and so on; the masses as one)
//   aos       one array of 24 doubles per particle
//
// and three sweeps of the soa arrays for a bed of one kind of particle (one m, 1/m and
// 1/I, no mass arrays read), one axis at a time over blocks of 32768 as cdm's pass:
//
//   one-now   cdm's pass today: per axis position, half-step velocity and force read and
//             written, predicted velocity written only (its lines still read for
//             ownership); per spin axis the same without position. 21 arrays read,
//             336 B per particle-step
//   one-lastf the last force kept instead of the half-step velocity (bench/README.md,
//             session 17): per axis position, predicted velocity and last force read and
//             written, force read only. 21 arrays read as well, but 6 fewer written
//             back: 288 B
//   one-3r    only what cannot be avoided: per axis position and half-step velocity read
//             and written, force read only; nothing written that is not read. 15 arrays
//             read, 192 B: the most that accumulators the pass never resets could give
//             (the step stamp they would need is not counted)
//
// Usage: pass_probe [--threads=K] [N ...]   (default 1e4 1e5 1e6; one thread). With K
// threads each sweep is split into K contiguous equal shares, as cdm's pass is: what
// the memory system gives K cores for the pass's traffic (issue #7: two threads
// against one at 1e6).
// Output: a whitespace table: per N and layout, the median time per particle (wall
// time of the whole sweep) of 5 timed batches of sweeps (each batch at least 0.1 s),
// the implied bandwidth (for the row's bytes, bytes_of) and the data's size (24 doubles per
// particle for every row; one-now and one-lastf touch 21 of them, one-3r 15).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <omp.h>
#include <string_view>
#include <vector>

namespace {

constexpr int nq = 24;  // doubles per particle
// Quantity order: 0-2 x, 3-5 half-step velocity, 6-8 force, 9-11 half-step spin,
// 12-14 torque, 15 inverse mass, 16 inverse inertia, 17 mass, 18-20 velocity, 21-23 spin.

/// Where quantity q of particle i lives: base[q] + i * stride[q] (in doubles).
struct Layout {
  const char* name;
  double* base[nq];
  std::size_t stride[nq];
};

struct Arena {
  std::unique_ptr<char, decltype(&std::free)> mem{nullptr, &std::free};
  Layout layout{};
};

Arena make(const char* kind, std::size_t n) {
  Arena a;
  const std::size_t page = 4096;
  const std::size_t array = ((n * sizeof(double) + page - 1) / page + 1) * page;  // one quantity, page-rounded
  const std::size_t total = nq * array + 2 * page;
  a.mem.reset(static_cast<char*>(std::aligned_alloc(page, total)));
  if (!a.mem) {
    std::fprintf(stderr, "pass_probe: cannot allocate %zu bytes for N = %zu\n", total, n);
    std::exit(1);
  }
  char* m = a.mem.get();
  std::memset(m, 0, total);
  Layout& l = a.layout;
  const std::string_view k = kind;
  if (k == "soa" || k.starts_with("soa-axis") || k == "soa-page" || k.starts_with("one-")) {
    const std::size_t skew = k == "soa-page" ? 0 : 16;
    for (int q = 0; q < nq; ++q) {
      l.base[q] = reinterpret_cast<double*>(m + q * array + q * skew);
      l.stride[q] = 1;
    }
  } else if (k == "vec3") {
    for (int q = 0; q < nq; ++q) {
      l.base[q] = reinterpret_cast<double*>(m + (q / 3) * 3 * array + 16 * (q / 3)) + q % 3;
      l.stride[q] = 3;
    }
  } else {
    for (int q = 0; q < nq; ++q) {
      l.base[q] = reinterpret_cast<double*>(m) + q;
      l.stride[q] = nq;
    }
  }
  l.name = kind;
  for (std::size_t i = 0; i < n; ++i) {
    l.base[15][i * l.stride[15]] = 1.0 / 1.3e-6;
    l.base[16][i * l.stride[16]] = 1.0 / 1.3e-13;
    l.base[17][i * l.stride[17]] = 1.3e-6;
  }
  return a;
}

// One sweep: half kick, drift, predicted velocity and spin, forces set to (a tiny)
// weight, torques zeroed: the pass's reads and writes. Written out per layout, each
// array's pointer in a local, as real code would hold them.
constexpr double dt = 1.6e-6, h = 0.5 * dt, g = -9.81e-9;

void sweep_soa(const Layout& l, std::size_t first, std::size_t end) {
  double *const x = l.base[0], *const y = l.base[1], *const z = l.base[2];
  double *const hvx = l.base[3], *const hvy = l.base[4], *const hvz = l.base[5];
  double *const fx = l.base[6], *const fy = l.base[7], *const fz = l.base[8];
  double *const hwx = l.base[9], *const hwy = l.base[10], *const hwz = l.base[11];
  double *const tx = l.base[12], *const ty = l.base[13], *const tz = l.base[14];
  const double *const im = l.base[15], *const ii = l.base[16], *const m = l.base[17];
  double *const vx = l.base[18], *const vy = l.base[19], *const vz = l.base[20];
  double *const wx = l.base[21], *const wy = l.base[22], *const wz = l.base[23];
  for (std::size_t i = first; i < end; ++i) {
    const double b = h * im[i], c = h * ii[i];
    const double ux = hvx[i] + b * fx[i], uy = hvy[i] + b * fy[i], uz = hvz[i] + b * fz[i];
    hvx[i] = ux; hvy[i] = uy; hvz[i] = uz;
    x[i] += dt * ux; y[i] += dt * uy; z[i] += dt * uz;
    vx[i] = ux + b * fx[i]; vy[i] = uy + b * fy[i]; vz[i] = uz + b * fz[i];
    fx[i] = 0.0; fy[i] = 0.0; fz[i] = m[i] * g;
    const double sx = hwx[i] + c * tx[i], sy = hwy[i] + c * ty[i], sz = hwz[i] + c * tz[i];
    hwx[i] = sx; hwy[i] = sy; hwz[i] = sz;
    wx[i] = sx + c * tx[i]; wy[i] = sy + c * ty[i]; wz[i] = sz + c * tz[i];
    tx[i] = 0.0; ty[i] = 0.0; tz[i] = 0.0;
  }
}

/// The soa layout one axis at a time over blocks of particles (cdm's verlet_pass): the
/// same arithmetic per particle as sweep_soa, in 6 loops of 4 to 6 arrays each.
template <std::size_t block>
void sweep_soa_axis(const Layout& l, std::size_t first, std::size_t end) {
  const double *const im = l.base[15], *const ii = l.base[16], *const m = l.base[17];
  auto axis = [&](int q, double gq, std::size_t i0, std::size_t i1) {
    double *const X = l.base[q], *const HV = l.base[3 + q], *const F = l.base[6 + q], *const V = l.base[18 + q];
    for (std::size_t i = i0; i < i1; ++i) {
      const double b = h * im[i];
      const double u = HV[i] + b * F[i];
      HV[i] = u;
      X[i] += dt * u;
      V[i] = u + b * F[i];
      F[i] = m[i] * gq;
    }
  };
  auto spin = [&](int q, std::size_t i0, std::size_t i1) {
    double *const HW = l.base[9 + q], *const T = l.base[12 + q], *const W = l.base[21 + q];
    for (std::size_t i = i0; i < i1; ++i) {
      const double c = h * ii[i];
      const double s = HW[i] + c * T[i];
      HW[i] = s;
      W[i] = s + c * T[i];
      T[i] = 0.0;
    }
  };
  for (std::size_t i0 = first; i0 < end; i0 += block) {
    const std::size_t i1 = std::min(end, i0 + block);
    axis(0, 0.0, i0, i1); axis(1, 0.0, i0, i1); axis(2, g, i0, i1);
    spin(0, i0, i1); spin(1, i0, i1); spin(2, i0, i1);
  }
}

/// The soa arrays of a bed of one kind of particle, one axis at a time over blocks of
/// 32768 particles, with the traffic of variant @p Kind (one-now, one-lastf, one-3r; see
/// the top of the file). The arithmetic is the pass's where the variant keeps the same
/// quantities, and stands in for it where not (one-3r writes no predicted velocity); it
/// is the traffic that is measured. The mass arrays are not read.
enum class OneMass { now, lastf, three_reads };
template <OneMass Kind>
void sweep_one(const Layout& l, std::size_t first, std::size_t end) {
  constexpr std::size_t block = 32768;
  const double b = h / 1.3e-6, c = h / 1.3e-13, m = 1.3e-6;
  auto axis = [&](int q, double gq, std::size_t i0, std::size_t i1) {
    // HV is the half-step velocity (now, three_reads) or the last force (lastf).
    double *const X = l.base[q], *const HV = l.base[3 + q], *const F = l.base[6 + q], *const V = l.base[18 + q];
    for (std::size_t i = i0; i < i1; ++i) {
      if constexpr (Kind == OneMass::now) {
        const double u = HV[i] + b * F[i];
        HV[i] = u;
        X[i] += dt * u;
        V[i] = u + b * F[i];
        F[i] = m * gq;
      } else if constexpr (Kind == OneMass::lastf) {
        const double u = (V[i] - b * HV[i]) + 2.0 * b * F[i];
        X[i] += dt * u;
        V[i] = u + b * F[i];
        HV[i] = m * gq;
      } else {
        const double u = HV[i] + 2.0 * b * F[i];
        HV[i] = u;
        X[i] += dt * u;
      }
    }
  };
  auto spin = [&](int q, std::size_t i0, std::size_t i1) {
    double *const HW = l.base[9 + q], *const T = l.base[12 + q], *const W = l.base[21 + q];
    for (std::size_t i = i0; i < i1; ++i) {
      if constexpr (Kind == OneMass::now) {
        const double s = HW[i] + c * T[i];
        HW[i] = s;
        W[i] = s + c * T[i];
        T[i] = 0.0;
      } else if constexpr (Kind == OneMass::lastf) {
        const double s = (W[i] - c * HW[i]) + 2.0 * c * T[i];
        W[i] = s + c * T[i];
        HW[i] = 0.0;
      } else {
        HW[i] += 2.0 * c * T[i];
      }
    }
  };
  for (std::size_t i0 = first; i0 < end; i0 += block) {
    const std::size_t i1 = std::min(end, i0 + block);
    axis(0, 0.0, i0, i1); axis(1, 0.0, i0, i1); axis(2, g, i0, i1);
    spin(0, i0, i1); spin(1, i0, i1); spin(2, i0, i1);
  }
}

/// Bytes per particle-step of @p kind: a double read and written counts 16, read only
/// 8, written only 16 (its line is read for ownership).
double bytes_of(std::string_view kind) {
  if (kind == "one-now") return 3 * (3 * 16 + 16) + 3 * (2 * 16 + 16);
  if (kind == "one-lastf") return 3 * (3 * 16 + 8) + 3 * (2 * 16 + 8);
  if (kind == "one-3r") return 3 * (2 * 16 + 8) + 3 * (16 + 8);
  return 15 * 16 + 3 * 8 + 6 * 16;
}

/// Groups of three quantities (S = 3, one array each) or all 24 in one (S = 24): the
/// same arithmetic on p[q] + i * S.
template <std::size_t S>
void sweep_packed(const Layout& l, std::size_t first, std::size_t end) {
  double *const X = l.base[0], *const HV = l.base[3], *const F = l.base[6], *const HW = l.base[9];
  double *const T = l.base[12], *const M = l.base[15], *const V = l.base[18], *const W = l.base[21];
  for (std::size_t i = first; i < end; ++i) {
    const std::size_t k = i * S;
    const double b = h * M[k], c = h * M[k + 1];
    const double ux = HV[k] + b * F[k], uy = HV[k + 1] + b * F[k + 1], uz = HV[k + 2] + b * F[k + 2];
    HV[k] = ux; HV[k + 1] = uy; HV[k + 2] = uz;
    X[k] += dt * ux; X[k + 1] += dt * uy; X[k + 2] += dt * uz;
    V[k] = ux + b * F[k]; V[k + 1] = uy + b * F[k + 1]; V[k + 2] = uz + b * F[k + 2];
    F[k] = 0.0; F[k + 1] = 0.0; F[k + 2] = M[k + 2] * g;
    const double sx = HW[k] + c * T[k], sy = HW[k + 1] + c * T[k + 1], sz = HW[k + 2] + c * T[k + 2];
    HW[k] = sx; HW[k + 1] = sy; HW[k + 2] = sz;
    W[k] = sx + c * T[k]; W[k + 1] = sy + c * T[k + 1]; W[k + 2] = sz + c * T[k + 2];
    T[k] = 0.0; T[k + 1] = 0.0; T[k + 2] = 0.0;
  }
}

/// Particles [i0, i1) (each sweep_* takes its range as [first, end)).
void sweep_range(const Layout& l, std::size_t i0, std::size_t i1) {
  switch (l.stride[0]) {
    case 1:
      if (std::string_view(l.name) == "soa-axis") sweep_soa_axis<32768>(l, i0, i1);
      else if (std::string_view(l.name) == "soa-axis-2k") sweep_soa_axis<2048>(l, i0, i1);
      else if (std::string_view(l.name) == "one-now") sweep_one<OneMass::now>(l, i0, i1);
      else if (std::string_view(l.name) == "one-lastf") sweep_one<OneMass::lastf>(l, i0, i1);
      else if (std::string_view(l.name) == "one-3r") sweep_one<OneMass::three_reads>(l, i0, i1);
      else sweep_soa(l, i0, i1);
      break;
    case 3: sweep_packed<3>(l, i0, i1); break;
    default: sweep_packed<nq>(l, i0, i1); break;
  }
}

/// All n particles, on @p threads threads, each a contiguous equal share (as cdm's
/// pass splits them, thread_range).
void sweep(const Layout& l, std::size_t n, int threads) {
  if (threads == 1) {
    sweep_range(l, 0, n);
    return;
  }
#pragma omp parallel num_threads(threads)
  {
    const auto t = static_cast<std::size_t>(omp_get_thread_num()), nt = static_cast<std::size_t>(omp_get_num_threads());
    sweep_range(l, n * t / nt, n * (t + 1) / nt);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes;
  int threads = 1;
  for (int k = 1; k < argc; ++k) {
    char* end = nullptr;
    const std::string_view arg = argv[k];
    if (arg.starts_with("--threads=")) {
      const long t = std::strtol(argv[k] + 10, &end, 10);
      if (end == argv[k] + 10 || *end != '\0' || t < 1 || t > 64) {
        std::fprintf(stderr, "pass_probe: argument %d: '%s': expected --threads=K with K an integer in [1, 64]\n", k,
                     argv[k]);
        return 2;
      }
      threads = static_cast<int>(t);
      continue;
    }
    const double v = std::strtod(argv[k], &end);
    if (end == argv[k] || *end != '\0' || !(v >= 1.0) || v > 1e8) {
      std::fprintf(stderr, "pass_probe: argument %d: '%s' is not a particle count in [1, 1e8]\n", k, argv[k]);
      return 2;
    }
    sizes.push_back(static_cast<std::size_t>(v));
  }
  if (sizes.empty()) sizes = {10000, 100000, 1000000};
  std::printf("# pass_probe: velocity Verlet's pass, %g B per particle-step (one-*: %g, %g, %g), %d thread(s)\n",
              bytes_of("soa"), bytes_of("one-now"), bytes_of("one-lastf"), bytes_of("one-3r"), threads);
  std::printf("# N  layout  time_per_particle[ns]  bandwidth[GB/s]  data[MB]\n");
  using clock = std::chrono::steady_clock;
  for (const std::size_t n : sizes) {
    for (const char* kind :
         {"soa", "soa-axis", "soa-axis-2k", "soa-page", "vec3", "aos", "one-now", "one-lastf", "one-3r"}) {
      const Arena a = make(kind, n);
      sweep(a.layout, n, threads);  // caches warm
      std::size_t reps = 1;  // sweeps per batch: enough for 0.1 s
      for (;;) {
        const auto t0 = clock::now();
        for (std::size_t r = 0; r < reps; ++r) sweep(a.layout, n, threads);
        if (std::chrono::duration<double>(clock::now() - t0).count() >= 0.1) break;
        reps *= 2;
      }
      std::vector<double> t;
      for (int batch = 0; batch < 5; ++batch) {
        const auto t0 = clock::now();
        for (std::size_t r = 0; r < reps; ++r) sweep(a.layout, n, threads);
        t.push_back(std::chrono::duration<double>(clock::now() - t0).count() / static_cast<double>(reps * n));
      }
      std::sort(t.begin(), t.end());
      const double med = t[t.size() / 2];
      volatile double sink = a.layout.base[0][(n / 2) * a.layout.stride[0]];  // the sweeps' results are used
      (void)sink;
      std::printf("%zu %s %.2f %.1f %.1f\n", n, a.layout.name, med * 1e9, bytes_of(kind) / med * 1e-9,
                  nq * 8.0 * n / 1e6);
      std::fflush(stdout);
    }
  }
  return 0;
}
