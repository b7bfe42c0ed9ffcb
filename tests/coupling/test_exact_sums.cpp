// Sums whose result does not depend on the order of their terms (exact_sums.hpp), and
// the deposit built on them: the same terms in another order, or split into partial sums
// added up afterwards (as MPI ranks do), give the same bits; each sum is within one unit
// per term of the exact sum; a mean split among processes (exact_mean) is the whole one's,
// and none where a term is not finite; and the particles' impulses and volumes deposited
// in another order give the same cells, where plain running sums of doubles do not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <optional>
#include <random>
#include <vector>

#include "cdm/solver/coupling/two_way_exchange.hpp"
#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/particle_store.hpp"

namespace {

using namespace cdm;

struct Term {
  std::size_t sum;
  double v;
};

/// Terms of magnitudes spread over eight decades and both signs, into @p sums sums.
std::vector<Term> terms(std::size_t n, std::size_t sums, double bound) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<Term> t(n);
  for (auto& x : t) {
    x.sum = static_cast<std::size_t>(u01(rng) * static_cast<double>(sums)) % sums;
    x.v = bound * (u01(rng) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, -8.0 * u01(rng));
  }
  return t;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(ExactSums, OrderAndSplitGiveTheSameBits) {
  const std::size_t n = 20000, nsums = 7;
  const double bound = 3.7e-5;
  std::vector<Term> t = terms(n, nsums, bound);
  auto sum_of = [&](const std::vector<Term>& ts, std::size_t first, std::size_t last, ExactSums& s) {
    s.reset(nsums, bound, static_cast<double>(n) * bound);
    for (std::size_t k = first; k < last; ++k) s.add(ts[k].sum, ts[k].v);
  };
  ExactSums forward, shuffled, lower, upper;
  sum_of(t, 0, n, forward);
  std::vector<Term> mixed = t;
  std::shuffle(mixed.begin(), mixed.end(), std::mt19937_64(5));
  sum_of(mixed, 0, n, shuffled);
  // Two "ranks": partial sums over two halves of the shuffled terms, added as integers.
  sum_of(mixed, 0, n / 3, lower);
  sum_of(mixed, n / 3, n, upper);
  for (std::size_t k = 0; k < nsums; ++k) lower.data()[k] += upper.data()[k];
  // Plain running sums in the two orders, to show that the order would matter.
  std::vector<double> plain_forward(nsums, 0.0), plain_shuffled(nsums, 0.0);
  for (const Term& x : t) plain_forward[x.sum] += x.v;
  for (const Term& x : mixed) plain_shuffled[x.sum] += x.v;
  int plain_differ = 0;
  for (std::size_t k = 0; k < nsums; ++k) {
    EXPECT_TRUE(same_bits(forward.value(k), shuffled.value(k))) << "sum " << k;
    EXPECT_TRUE(same_bits(forward.value(k), lower.value(k))) << "sum " << k;
    plain_differ += same_bits(plain_forward[k], plain_shuffled[k]) ? 0 : 1;
  }
  EXPECT_GT(plain_differ, 0) << "these terms do not test the order";
}

TEST(ExactSums, AMeanSplitIntoPartsHasTheSameBitsAndNoneWhereATermIsNotFinite) {
  const std::size_t n = 9000;
  std::vector<double> x;
  for (const Term& t : terms(n, 1, 2.5e3)) x.push_back(t.v);
  // One part, then three "processes": each visits its run; the largest magnitude and the
  // sums are reduced over them as MPI would (each process's partial sum first, then the
  // mean as process 0 gets it, its sum replaced by the total).
  const std::size_t cut[4] = {0, n / 5, n / 2, n};
  auto run = [&](std::size_t r) {
    return [&x, k0 = cut[r], k1 = cut[r + 1]](auto&& f) {
      for (std::size_t k = k0; k < k1; ++k) f(x[k]);
    };
  };
  const auto whole = exact_mean(
      static_cast<double>(n), [&](auto&& f) { for (double v : x) f(v); }, [](double m) { return m; },
      [](ExactSums&) {});
  ASSERT_TRUE(whole.has_value());
  double largest = 0.0;
  for (double v : x) largest = std::max(largest, std::abs(v));
  const auto to_all = [&](double) { return largest; };
  std::int64_t total = 0;
  for (std::size_t r = 0; r < 3; ++r)
    exact_mean(static_cast<double>(n), run(r), to_all, [&](ExactSums& s) { total += s.data()[0]; });
  const auto split = exact_mean(static_cast<double>(n), run(0), to_all, [&](ExactSums& s) { s.data()[0] = total; });
  ASSERT_TRUE(split.has_value());
  EXPECT_TRUE(same_bits(*whole, *split));
  double plain = 0.0;
  for (double v : x) plain += v;
  EXPECT_NEAR(*whole, plain / static_cast<double>(n), 1e-12 * largest);
  // A NaN anywhere, first or not, leaves no mean.
  for (const std::size_t at : {std::size_t{0}, n / 3}) {
    std::vector<double> y = x;
    y[at] = std::nan("");
    EXPECT_FALSE(exact_mean(
                     static_cast<double>(n), [&](auto&& f) { for (double v : y) f(v); },
                     [](double m) { return m; }, [](ExactSums&) {})
                     .has_value());
  }
}

TEST(ExactSums, EachSumWithinOneUnitPerTermOfTheExactSum) {
  const std::size_t n = 20000, nsums = 5;
  const double bound = 2.5e3;
  const std::vector<Term> t = terms(n, nsums, bound);
  ExactSums s;
  s.reset(nsums, bound, static_cast<double>(n) * bound);
  std::vector<long double> exact(nsums, 0.0L);
  std::vector<std::size_t> count(nsums, 0);
  for (const Term& x : t) {
    s.add(x.sum, x.v);
    exact[x.sum] += static_cast<long double>(x.v);
    ++count[x.sum];
  }
  // The unit: 2^-62 of the sums' bound, rounded up to a power of two (at most 2^-61 of it).
  const double unit = std::ldexp(static_cast<double>(n) * bound, -61);
  for (std::size_t k = 0; k < nsums; ++k) {
    const double err = std::abs(static_cast<double>(static_cast<long double>(s.value(k)) - exact[k]));
    EXPECT_LE(err, static_cast<double>(count[k]) * unit + 1e-15 * std::abs(static_cast<double>(exact[k])))
        << "sum " << k;
  }
}

TEST(ExactSums, ATermAtTheBoundInEverySlotDoesNotOverflow) {
  const std::size_t n = 1000;
  const double bound = 1.0;
  ExactSums s;
  s.reset(1, bound, static_cast<double>(n) * bound);
  for (std::size_t k = 0; k < n; ++k) s.add(0, -bound);
  EXPECT_NEAR(s.value(0), -static_cast<double>(n), 1e-9);
}

fluid::GridSpec grid_spec() {
  fluid::GridSpec g;
  g.lo = {0.0, 0.0, 0.0};
  g.hi = {0.02, 0.04, 0.01};
  g.cells = {6, 12, 3};
  for (int f = 0; f < 6; ++f) g.faces[f].kind = fluid::BoundaryKind::no_slip;
  return g;
}

/// 300 particles with impulses, in the order @p order gives.
ParticleStore particles(const fluid::StaggeredGrid& g, const std::vector<std::size_t>& order) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<Vec3> x(order.size()), j(order.size());
  std::vector<double> d(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    x[k] = {g.lo(0) + u01(rng) * g.length(0), g.lo(1) + u01(rng) * g.length(1), g.lo(2) + u01(rng) * g.length(2)};
    j[k] = {1e-7 * (u01(rng) - 0.5), 1e-6 * u01(rng) * std::pow(10.0, -4.0 * u01(rng)), 1e-7 * (u01(rng) - 0.5)};
    d[k] = 2.0e-4 * (1.0 + 0.3 * u01(rng));
  }
  ParticleStore p;
  for (std::size_t k : order) p.add(x[k], {}, d[k], 2500.0, 0);
  p.enable_two_way();
  for (std::size_t s = 0; s < order.size(); ++s) {
    p.jx[s] = j[order[s]].x; p.jy[s] = j[order[s]].y; p.jz[s] = j[order[s]].z;
  }
  return p;
}

TEST(ExactSums, TheDepositGivesTheSameCellsInAnyParticleOrder) {
  const fluid::StaggeredGrid g(grid_spec());
  std::vector<std::size_t> forward(300), reversed(300);
  std::iota(forward.begin(), forward.end(), 0);
  std::iota(reversed.rbegin(), reversed.rend(), 0);
  ParticleStore a = particles(g, forward), b = particles(g, reversed);
  coupling::TwoWayExchange ea(g, true, coupling::Kernel::trilinear, 0.0), eb(g, true, coupling::Kernel::trilinear, 0.0);
  std::vector<double> eps_a, eps_b;
  ea.deposit_impulses_and_void_fraction(a, eps_a, 0.0);
  eb.deposit_impulses_and_void_fraction(b, eps_b, 0.0);
  ASSERT_EQ(eps_a.size(), eps_b.size());
  std::size_t nonzero = 0;
  for (std::size_t c = 0; c < eps_a.size(); ++c) {
    EXPECT_TRUE(same_bits(eps_a[c], eps_b[c])) << "cell " << c;
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_TRUE(same_bits(ea.reaction(axis)[c], eb.reaction(axis)[c])) << "cell " << c << ", axis " << axis;
      nonzero += ea.reaction(axis)[c] != 0.0 ? 1 : 0;
    }
  }
  EXPECT_GT(nonzero, 100u);
  // Emptied accumulators, and the momentum given to the gas equal and opposite to the
  // particles' (the balance is recorded when the reaction is applied).
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a.jy[i], 0.0);
  const ParticleStore before = particles(g, forward);
  double total = 0.0, given = 0.0;
  for (double jy : before.jy) total += jy;
  for (double r : ea.reaction(1)) given += r;
  EXPECT_NEAR(given, -total, 1e-12 * std::abs(total));
  // The every-step deposit likewise, over two steps (the second's impulses reversed),
  // and its sums still empty between steps.
  for (int step = 0; step < 2; ++step) {
    ParticleStore pa = particles(g, forward), pb = particles(g, reversed);
    if (step == 1)
      for (ParticleStore* p : {&pa, &pb})
        for (std::size_t i = 0; i < p->size(); ++i) {
          p->jx[i] = -p->jx[i]; p->jy[i] = -0.5 * p->jy[i];
        }
    ea.deposit_impulses(pa, 0.0);
    eb.deposit_impulses(pb, 0.0);
    for (std::size_t i = 0; i < pa.size(); ++i) EXPECT_EQ(pa.jy[i], 0.0);
  }
  std::size_t reached = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (std::size_t c = 0; c < eps_a.size(); ++c) {
      EXPECT_TRUE(same_bits(ea.reaction(axis)[c], eb.reaction(axis)[c])) << "cell " << c << ", axis " << axis;
      reached += ea.reaction(axis)[c] != 0.0 ? 1 : 0;
    }
  EXPECT_GT(reached, 100u);
  // Running sums of doubles, as the deposit once made them, do depend on the order of
  // these particles' terms.
  ParticleStore pa = particles(g, forward), pb = particles(g, reversed);
  const coupling::Deposition dep(g, coupling::Kernel::trilinear, 0.0);
  std::vector<double> ra(eps_a.size(), 0.0), rb(eps_a.size(), 0.0);
  for (std::size_t i = 0; i < pa.size(); ++i) {
    dep.for_each_weight(pa.position(i), [&](std::size_t c, double w) { ra[c] -= w * pa.jy[i]; });
    dep.for_each_weight(pb.position(i), [&](std::size_t c, double w) { rb[c] -= w * pb.jy[i]; });
  }
  std::size_t differ = 0;
  for (std::size_t c = 0; c < ra.size(); ++c) differ += same_bits(ra[c], rb[c]) ? 0 : 1;
  EXPECT_GT(differ, 0u) << "these particles do not test the order";
}

}  // namespace
