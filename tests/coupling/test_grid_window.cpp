// A grid's window (StaggeredGrid::set_window): the ghost fills and the gas field's derived
// arrays, computed on the window's planes only, equal those computed on every plane there,
// and leave every other plane as it was. This is what lets a process sharing the gas by
// planes keep only its reach current and still give the same bits as one process.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/fluid/gas_field.hpp"
#include "resident.hpp"

namespace {

using namespace cdm;
using namespace cdm::fluid;

/// A 3D box of 5 × 4 × 10 cells, inflow below (y), an outlet above, no-slip walls along x
/// and z (or, @p periodic_z, z periodic).
GasSpec column(bool periodic_z = false) {
  GasSpec s;
  s.grid.lo = {0, 0, 0};
  s.grid.hi = {0.5, 0.4, 1.0};
  s.grid.cells = {5, 4, 10};
  s.grid.faces[0].kind = s.grid.faces[1].kind = BoundaryKind::no_slip;
  s.grid.faces[2] = {BoundaryKind::velocity_inlet, 0.3, 0.0};
  s.grid.faces[3] = {BoundaryKind::pressure_outlet, 0.0, 100.0};
  s.grid.faces[4].kind = s.grid.faces[5].kind = periodic_z ? BoundaryKind::periodic : BoundaryKind::no_slip;
  s.density = 1.2;
  s.viscosity = 1.8e-5;
  s.interpolation = InterpolationScheme::paper_lagrange2;
  return s;
}

/// Values that differ everywhere, ghosts included, from a seed.
std::vector<double> scrambled(std::size_t n, std::uint64_t seed) {
  std::vector<double> a(n);
  std::uint64_t x = seed * 0x9E3779B97F4A7C15ull + 1;
  for (auto& v : a) {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    v = 0.5 + static_cast<double>(x >> 11) * 0x1.0p-53;
  }
  return a;
}

/// The plane along z (ghost planes from −ghosts) of flat index @p c.
int plane_of(const StaggeredGrid& g, std::size_t c) {
  return static_cast<int>((c - g.plane_start(-StaggeredGrid::ghosts)) / g.plane_size()) - StaggeredGrid::ghosts;
}

/// @p windowed (staggered as @p s) equals @p whole on the window's planes and its ghost
/// planes (window_lines) and @p before elsewhere.
void expect_window(const StaggeredGrid& g, Staggering s, const std::vector<double>& whole,
                   const std::vector<double>& windowed, const std::vector<double>& before, const char* what) {
  const auto [z0, z1] = g.window_lines(s);
  int differ = 0;
  for (std::size_t c = 0; c < whole.size(); ++c) {
    const int k = plane_of(g, c);
    const double want = k >= z0 && k <= z1 ? whole[c] : before[c];
    if (windowed[c] != want && ++differ <= 3)
      ADD_FAILURE() << what << ": window [" << g.window().first << ", " << g.window().second << ") plane " << k
                    << " index " << c << ": " << windowed[c] << ", want " << want;
  }
  EXPECT_EQ(differ, 0) << what;
}

const std::pair<int, int> windows[] = {{3, 6}, {0, 4}, {6, 10}, {0, 10}, {4, 5}};

/// Each window, on the bounded column and along a periodic z (where a window that
/// reaches an end is whole: its ghosts wrap to the planes past the other end).
struct Case {
  bool periodic;
  int lo, hi;
};
std::vector<Case> cases() {
  std::vector<Case> c;
  for (const bool periodic : {false, true})
    for (const auto& [lo, hi] : windows) c.push_back({periodic, lo, hi});
  return c;
}
std::pair<int, int> expected_window(const Case& c) {
  return c.periodic && (c.lo == 0 || c.hi == 10) ? std::pair{0, 10} : std::pair{c.lo, c.hi};
}

TEST(GridWindow, GhostFillsVisitTheWindowsPlanesOnly) {
  for (const Case& cs : cases()) {
    StaggeredGrid whole_grid(column(cs.periodic).grid), g(column(cs.periodic).grid);
    g.set_window(cs.lo, cs.hi);
    ASSERT_EQ(g.window(), expected_window(cs));
    EXPECT_EQ(g.window_whole(), expected_window(cs) == (std::pair{0, 10}));
    std::uint64_t seed = 1;
    for (int kind = 0; kind < 4; ++kind) {
      const std::vector<double> before[3] = {scrambled(g.padded_size(), seed), scrambled(g.padded_size(), seed + 1),
                                             scrambled(g.padded_size(), seed + 2)};
      seed += 3;
      std::vector<double> a[3] = {before[0], before[1], before[2]}, b[3] = {before[0], before[1], before[2]};
      auto fill = [&](const StaggeredGrid& grid, std::vector<double>* x) {
        if (kind == 0) grid.fill_velocity_ghosts(x[0], x[1], x[2]);
        if (kind == 1) grid.fill_scalar_ghosts(x[0]);
        if (kind == 2) grid.fill_pressure_ghosts(x[0]);
        if (kind == 3) grid.fill_even_ghosts(x[0], Staggering::w);
      };
      fill(whole_grid, a);
      fill(g, b);
      const Staggering s[4] = {Staggering::u, Staggering::centre, Staggering::centre, Staggering::w};
      for (int c = 0; c < 3; ++c)
        expect_window(g, kind == 0 ? static_cast<Staggering>(c) : s[kind], a[c], b[c], before[c], "ghost fill");
    }
  }
}

TEST(GridWindow, CopiesAndFillsCoverTheWindowsSpan) {
  StaggeredGrid g(column().grid);
  g.set_window(2, 7);
  const std::vector<double> from = scrambled(g.padded_size(), 7), before = scrambled(g.padded_size(), 8);
  std::vector<double> copied = before, filled = before, zero(g.padded_size(), 0.0);
  g.copy_window(from, copied);
  g.fill_window(filled, 0.0);
  expect_window(g, Staggering::w, from, copied, before, "copy");
  expect_window(g, Staggering::w, zero, filled, before, "fill");
  // A window beyond the grid is clamped to it; along a periodic z one that reaches an
  // end keeps every plane.
  g.set_window(-3, 40);
  EXPECT_TRUE(g.window_whole());
  StaggeredGrid p(column(true).grid);
  p.set_window(2, 7);
  EXPECT_EQ(p.window(), (std::pair{2, 7}));
  p.set_window(0, 7);
  EXPECT_TRUE(p.window_whole());
  p.set_window(2, 10);
  EXPECT_TRUE(p.window_whole());
}

TEST(GridWindow, TheGasFieldsDerivedArraysAreSetOnTheWindow) {
  for (const Case& cs : cases()) {
    const auto [lo, hi] = expected_window(cs);
    const GasSpec spec = column(cs.periodic);
    GasField whole(spec, {0, -9.81, 0}, true, true), part(spec, {0, -9.81, 0}, true, true);
    for (GasField* f : {&whole, &part}) {
      f->enable_superficial_velocity();
      f->enable_cell_pressure_gradient();
      const std::size_t n = f->grid().padded_size();
      f->u = scrambled(n, 1), f->v = scrambled(n, 2), f->w = scrambled(n, 3);
      f->p = scrambled(n, 4), f->eps_g = scrambled(n, 5);
      f->refresh();  // every plane: the derived arrays as they were before the window
    }
    const std::vector<double> gp_before[3] = {part.gpx, part.gpy, part.gpz};
    const std::vector<double> cell_before[3] = {part.cell_gpx, part.cell_gpy, part.cell_gpz};
    // New values everywhere; the windowed field is refreshed on its window only.
    for (GasField* f : {&whole, &part}) {
      const std::size_t n = f->grid().padded_size();
      f->u = scrambled(n, 11), f->v = scrambled(n, 12), f->w = scrambled(n, 13), f->p = scrambled(n, 14);
    }
    const std::vector<double> p_before = part.p;
    part.hold_planes(lo, hi);
    whole.refresh();
    part.refresh();
    const StaggeredGrid& g = part.grid();
    expect_window(g, Staggering::centre, whole.p, part.p, p_before, "pressure ghosts");
    const std::vector<double>* gw[3] = {&whole.gpx, &whole.gpy, &whole.gpz};
    const std::vector<double>* gp[3] = {&part.gpx, &part.gpy, &part.gpz};
    const std::vector<double>* cw[3] = {&whole.cell_gpx, &whole.cell_gpy, &whole.cell_gpz};
    const std::vector<double>* cp[3] = {&part.cell_gpx, &part.cell_gpy, &part.cell_gpz};
    for (int a = 0; a < 3; ++a) {
      expect_window(g, static_cast<Staggering>(a), *gw[a], *gp[a], gp_before[a], "face pressure gradient");
      // The cell gradients are set on the window's cells (not its ghost planes).
      const auto [k0, k1] = g.window_planes(Staggering::centre);
      for (int k = 0; k < g.n(2); ++k)
        for (int j = 0; j < g.n(1); ++j)
          for (int i = 0; i < g.n(0); ++i) {
            const std::size_t c = g.at(i, j, k);
            EXPECT_EQ((*cp[a])[c], k >= k0 && k < k1 ? (*cw[a])[c] : cell_before[a][c]) << "cell gradient " << a;
          }
    }
    // What a particle inside the window reads, two planes from its edges, is the same.
    for (double z = 0.05; z < 1.0; z += 0.1) {
      const int k = static_cast<int>(z * 10.0);
      if ((k < lo + 2 && lo > 0) || (k >= hi - 2 && hi < 10)) continue;
      const Vec3 x{0.23, 0.17, z};
      EXPECT_EQ(whole.velocity_at(x).z, part.velocity_at(x).z);
      EXPECT_EQ(whole.pressure_gradient_at(x).z, part.pressure_gradient_at(x).z);
      EXPECT_EQ(whole.superficial_velocity_at(x).y, part.superficial_velocity_at(x).y);
    }
  }
}

TEST(GridWindow, ZeroingBeyondTheWindowKeepsItAndGivesBackTheRest) {
  // Planes of 45 × 45 padded values (16 KB, whole pages) so that pages lie wholly beyond.
  GasSpec spec = column();
  spec.grid.cells = {40, 40, 40};
  StaggeredGrid g(spec.grid);
  // A new array commits no page.
  std::vector<double> fresh = g.make_array();
  EXPECT_FALSE(cdm_test::resident(fresh.data() + fresh.size() / 2));
  const std::size_t moves = g.window_moves();
  g.zero_outside_window(fresh);  // whole window: nothing to do
  g.set_window(10, 20);
  g.set_window(10, 20);
  EXPECT_EQ(g.window_moves(), moves + 1) << "only a change counts";
  const std::vector<double> before = scrambled(g.padded_size(), 21), zero(g.padded_size(), 0.0);
  std::vector<double> a = before;
  g.zero_outside_window(a);
  EXPECT_FALSE(cdm_test::resident(a.data() + g.plane_start(2)));
  EXPECT_FALSE(cdm_test::resident(a.data() + g.plane_start(30)));
  EXPECT_TRUE(cdm_test::resident(a.data() + g.plane_start(15)));
  expect_window(g, Staggering::w, before, a, zero, "zeroed beyond the window");
  // Three values a sample, interleaved: the window's samples' three kept.
  std::vector<double> three = scrambled(3 * g.padded_size(), 22), three_before = three;
  g.zero_outside_window(three.data(), 3 * sizeof(double));
  const auto [lo, hi] = g.window_span();
  for (std::size_t c = 0; c < three.size(); ++c)
    if (three[c] != (c >= 3 * lo && c < 3 * hi ? three_before[c] : 0.0)) {
      ADD_FAILURE() << "interleaved value " << c << " (sample " << c / 3 << ", window [" << lo << ", " << hi << "))";
      break;
    }
  // An array of another size is left alone.
  std::vector<double> other = scrambled(100, 23), other_before = other;
  g.zero_outside_window(other);
  EXPECT_EQ(other, other_before);
}

TEST(GridWindow, AFieldStartedOnPlanesAndARestartReadTouchOnlyThem) {
  GasSpec spec = column();
  spec.grid.cells = {40, 40, 40};
  // A field that holds planes 10 to 20 from the start: the gas fraction is one there, and
  // nothing beyond them is committed.
  GasField f(spec, {0, -9.81, 0}, true, true, {10, 20});
  const StaggeredGrid& g = f.grid();
  EXPECT_EQ(g.window(), (std::pair{10, 20}));
  EXPECT_EQ(f.eps_g[g.at(3, 3, 15)], 1.0);
  for (const std::vector<double>* a : {&f.u, &f.v, &f.w, &f.p, &f.eps_g})
    for (const int k : {2, 30}) {
      EXPECT_FALSE(cdm_test::resident(a->data() + g.plane_start(k))) << "plane " << k;
      EXPECT_EQ((*a)[g.at(3, 3, k)], 0.0);
    }
  // A restart reads an array's window and reads past the rest, which stays uncommitted;
  // what follows the array is read as written.
  const std::vector<double> saved = scrambled(g.padded_size(), 31);
  const double after = 0.375;
  std::vector<char> bytes(sizeof(std::uint64_t) + saved.size() * sizeof(double) + sizeof after);
  const std::uint64_t n = saved.size();
  std::memcpy(bytes.data(), &n, sizeof n);
  std::memcpy(bytes.data() + sizeof n, saved.data(), saved.size() * sizeof(double));
  std::memcpy(bytes.data() + bytes.size() - sizeof after, &after, sizeof after);
  InArchive in(bytes.data(), bytes.size());
  std::vector<double> a = g.make_array();
  g.get_window(in, a);
  double next = 0.0;
  in.get(next);
  EXPECT_EQ(next, after);
  EXPECT_TRUE(in.done());
  // (Before a pass reads them: a read maps the zero page, which mincore counts.)
  EXPECT_FALSE(cdm_test::resident(a.data() + g.plane_start(2)));
  EXPECT_FALSE(cdm_test::resident(a.data() + g.plane_start(30)));
  expect_window(g, Staggering::w, saved, a, std::vector<double>(g.padded_size(), 0.0), "read");
  // An array of another length is refused.
  InArchive shorter(bytes.data(), bytes.size());
  const std::uint64_t fewer = n - 1;
  std::memcpy(bytes.data(), &fewer, sizeof fewer);
  EXPECT_THROW(g.get_window(shorter, a), ArchiveError);
}

TEST(GridWindow, SumsByCellsCommitOnlyThePagesAddedTo) {
  // Integer sums by cells (TwoWayExchange's deposits), of which a process adds to its
  // planes only: a new set costs nothing until a term is added.
  const std::size_t n = 1u << 20;
  ExactSums s;
  s.reset(n, 1.0, 1.0);
  EXPECT_FALSE(cdm_test::resident(s.data() + n / 2));
  s.add(n / 4, 0.5);
  EXPECT_TRUE(cdm_test::resident(s.data() + n / 4));
  EXPECT_FALSE(cdm_test::resident(s.data() + n / 2));
  EXPECT_EQ(s.value(n / 4), 0.5);
  EXPECT_EQ(s.value(n / 2), 0.0);
  // A thread's partial sums (reset_like) likewise; what they add to is a run of cells.
  ExactSums t;
  t.reset_like(s);
  EXPECT_FALSE(cdm_test::resident(t.data() + n / 2));
  t.add(n / 8, 0.25);
  s.add(t, n / 8, n / 8 + 1);
  EXPECT_EQ(s.value(n / 8), 0.25);
  t.clear(n / 8, n / 8 + 1);
  t.reset_like(s);  // as many, zero: not touched
  EXPECT_FALSE(cdm_test::resident(t.data() + n / 2));
  EXPECT_EQ(t.value(n / 8), 0.0);
}

}  // namespace
