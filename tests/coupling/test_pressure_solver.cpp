// The pressure-equation solver: the multigrid backend (hypre PCG + PFMG/SMG) against the
// direct one (Eigen LDLᵀ) on random coefficients d ∈ [0.4, 1] and random right-hand
// sides, in 2D and 3D, periodic, walled, inlet + outlet and without an outlet (singular:
// both hold cell 0 at φ = 0, so they solve the same system).
// The multigrid solution's true residual ‖b − Aφ‖/‖b‖ must be within the tolerance, and
// its distance to the direct solution within what the tolerance allows: ‖δφ‖/‖φ‖ ≤
// κ(A) ‖b − Aφ‖/‖b‖, with κ(A) ≤ 8 (max d/min d) Σ n_a² (the spread of the Laplacian's
// eigenvalues, 4Σ1/h² over π²/(4L²) at worst), taken with a factor 10 of margin.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cdm/solver/fluid/pressure_solver.hpp"

namespace {

using namespace cdm;
using namespace cdm::fluid;
using BK = BoundaryKind;

struct Case {
  const char* name;
  std::array<int, 3> n;
  bool two_d;
  std::array<BK, 3> lower, upper;  // per axis
};

GridSpec grid_of(const Case& c) {
  GridSpec s;
  s.lo = {0, 0, 0};
  s.hi = {1.0, 1.3, 0.7};
  s.cells = c.n;
  s.two_d = c.two_d;
  for (int a = 0; a < 3; ++a) {
    s.faces[2 * a].kind = c.lower[a];
    s.faces[2 * a + 1].kind = c.upper[a];
  }
  if (c.two_d) s.faces[4].kind = s.faces[5].kind = BK::periodic;
  return s;
}

struct Problem {
  std::array<std::vector<double>, 3> d;
  std::vector<double> b;
};

Problem random_problem(const StaggeredGrid& g, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> eps(0.4, 1.0), src(-1.0, 1.0);
  Problem p;
  for (auto& a : p.d) {
    a = g.make_array();
    for (double& x : a) x = eps(rng);
  }
  // A periodic axis's face n is its face 0: the same coefficient (as the projection's
  // periodic ghosts give it).
  for (int a = 0; a < g.dims(); ++a) {
    if (!g.spec().periodic(a)) continue;
    const int o1 = (a + 1) % 3, o2 = (a + 2) % 3;
    for (int q = 0; q < g.n(o2); ++q)
      for (int r = 0; r < g.n(o1); ++r) {
        int lo[3], hi[3];
        lo[a] = 0;
        hi[a] = g.n(a);
        lo[o1] = hi[o1] = r;
        lo[o2] = hi[o2] = q;
        p.d[a][g.at(hi[0], hi[1], hi[2])] = p.d[a][g.at(lo[0], lo[1], lo[2])];
      }
  }
  p.b.resize(g.cell_count());
  for (double& x : p.b) x = src(rng);
  return p;
}

/// b − Aφ from the solver's own stencil (independent of either backend's assembly).
std::vector<double> residual(const PressureSolver& ps, const StaggeredGrid& g, const Problem& p,
                             const std::vector<double>& b, const std::vector<double>& phi) {
  const std::array<const std::vector<double>*, 3> d{&p.d[0], &p.d[1], &p.d[2]};
  const int nx = g.n(0), ny = g.n(1), nz = g.n(2);
  auto idx = [&](int i, int j, int k) { return static_cast<std::size_t>(i + nx * (j + ny * k)); };
  std::vector<double> r(b.size());
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const auto s = ps.stencil(d, i, j, k);
        double ax = s.diag * phi[idx(i, j, k)];
        for (int a = 0; a < g.dims(); ++a)
          for (int side = 0; side < 2; ++side) {
            int c[3] = {i, j, k};
            c[a] = (c[a] + (side ? 1 : -1) + g.n(a)) % g.n(a);
            ax += s.off[static_cast<std::size_t>(2 * a + side)] * phi[idx(c[0], c[1], c[2])];
          }
        r[idx(i, j, k)] = b[idx(i, j, k)] - ax;
      }
  return r;
}

double norm2(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

class MultigridVsDirect : public ::testing::TestWithParam<Case> {};

TEST_P(MultigridVsDirect, AgreeWithinTheTolerance) {
  if (!cdm::fluid::multigrid_available()) GTEST_SKIP() << "built without MPI and hypre: no multigrid backend";
  const Case& c = GetParam();
  const StaggeredGrid g(grid_of(c));
  const Problem p = random_problem(g, 7);
  const std::array<const std::vector<double>*, 3> d{&p.d[0], &p.d[1], &p.d[2]};
  const double tol = 1e-10;

  PressureSolverSpec ds;
  ds.backend = PressureBackend::direct;
  PressureSolver direct(g, ds);
  std::vector<double> bd = p.b, phid(g.cell_count(), 0.0);
  direct.solve(d, bd, phid);

  {
    PressureSolverSpec ms;
    ms.backend = PressureBackend::multigrid;
    ms.tolerance = tol;
    PressureSolver mg(g, ms);
    std::vector<double> bm = p.b, phim(g.cell_count(), 0.0);
    const PressureSolveStats st = mg.solve(d, bm, phim);
    const double true_rel = norm2(residual(mg, g, p, bm, phim)) / norm2(bm);
    EXPECT_LE(st.relative_residual, tol) << mg.method();
    EXPECT_LE(true_rel, 1.01 * tol) << mg.method() << " (hypre reported " << st.relative_residual << ")";
    const std::vector<double>& a = phid;
    const std::vector<double>& m = phim;
    double sum_n2 = 0;
    for (int ax = 0; ax < g.dims(); ++ax) sum_n2 += static_cast<double>(g.n(ax)) * g.n(ax);
    const double kappa = 8.0 * (1.0 / 0.4) * sum_n2;
    double diff = 0, ref = 0;
    for (std::size_t q = 0; q < a.size(); ++q) {
      diff = std::max(diff, std::abs(a[q] - m[q]));
      ref = std::max(ref, std::abs(a[q]));
    }
    EXPECT_LE(diff / ref, 10.0 * kappa * tol) << mg.method();
    std::cout << c.name << " " << mg.method() << ": " << st.iterations << " iterations, residual "
              << st.relative_residual << ", |dphi|/|phi| " << diff / ref << "\n";
  }
}

const BK P = BK::periodic, W = BK::no_slip, F = BK::free_slip, I = BK::velocity_inlet, O = BK::pressure_outlet;

INSTANTIATE_TEST_SUITE_P(
    Grids, MultigridVsDirect,
    ::testing::Values(Case{"mms_periodic_16", {16, 16, 1}, true, {P, P, P}, {P, P, P}},
                      Case{"mms_periodic_128", {128, 128, 1}, true, {P, P, P}, {P, P, P}},
                      Case{"periodic_2d_odd_24x18", {24, 18, 1}, true, {P, P, P}, {P, P, P}},
                      Case{"walls_2d_no_outlet", {10, 14, 1}, true, {W, F, P}, {W, F, P}},
                      Case{"inlet_outlet_2d", {12, 20, 1}, true, {W, I, P}, {W, O, P}},
                      Case{"inlet_outlet_3d_16", {16, 16, 16}, false, {W, I, W}, {W, O, W}},
                      Case{"mueller_15x40x3", {15, 40, 3}, false, {W, I, W}, {W, O, W}},
                      Case{"fluidisation_4x32x2", {4, 32, 2}, false, {P, I, P}, {P, O, P}},
                      Case{"periodic_4x8x4_outlet", {4, 8, 4}, false, {P, I, P}, {P, O, P}},
                      Case{"periodic_2x6x2_no_outlet", {2, 6, 2}, false, {P, W, P}, {P, W, P}},
                      Case{"periodic_2d_2x9", {2, 9, 1}, true, {P, P, P}, {P, P, P}},
                      Case{"terminal_velocity_5x20x5", {5, 20, 5}, false, {P, I, P}, {P, O, P}},
                      Case{"suspension_3x3x3", {3, 3, 3}, false, {P, P, P}, {P, P, P}},
                      Case{"packed_bed_5x10x5", {5, 10, 5}, false, {P, P, P}, {P, P, P}},
                      Case{"periodic_3d_12x6x10", {12, 6, 10}, false, {P, P, P}, {P, P, P}},
                      Case{"walls_3d_no_outlet", {9, 7, 6}, false, {W, W, F}, {W, W, F}}),
    [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

// A second solve with the same d reuses the setup; a new d sets up again. A zero
// right-hand side gives φ = 0. For every backend of the build.
TEST(PressureSolver, SetupOncePerCoefficientsAndZeroRhs) {
  const StaggeredGrid g(grid_of(Case{"", {8, 8, 8}, false, {W, I, W}, {W, O, W}}));
  for (PressureBackend backend : {PressureBackend::direct, PressureBackend::multigrid}) {
    if (backend == PressureBackend::multigrid && !multigrid_available()) continue;
    Problem p = random_problem(g, 3);
    const std::array<const std::vector<double>*, 3> d{&p.d[0], &p.d[1], &p.d[2]};
    PressureSolverSpec spec;
    spec.backend = backend;
    PressureSolver ps(g, spec);
    std::vector<double> b = p.b, phi(g.cell_count(), 0.0);
    ps.solve(d, b, phi);
    b = p.b;
    const auto st = ps.solve(d, b, phi);  // warm start from the solution
    EXPECT_EQ(ps.setups(), 1u) << ps.method();
    EXPECT_LE(st.iterations, 1) << ps.method();
    p.d[1][g.at(3, 3, 3)] = 0.5;
    std::vector<double> zero(g.cell_count(), 0.0), phi0(g.cell_count(), 0.0);
    const auto z = ps.solve(d, zero, phi0);
    EXPECT_EQ(ps.setups(), 2u) << ps.method();
    EXPECT_EQ(z.relative_residual, 0.0) << ps.method();
    for (double x : phi0) EXPECT_EQ(x, 0.0) << ps.method();
  }
}

// The factorisation's work per cell: that of a line of cells, bounded; of a cube, growing
// with its side; a thin slab in between.
TEST(PressureSolver, FactorWorkGrowsWithTheGridsSmallerSides) {
  auto work = [](std::array<int, 3> n) {
    return direct_factor_work_per_cell(StaggeredGrid(grid_of(Case{"", n, false, {W, I, W}, {W, O, W}})));
  };
  EXPECT_LT(work({2, 200, 2}), 40.0);
  EXPECT_LT(work({8, 8, 8}), work({12, 12, 12}));
  EXPECT_LT(work({12, 12, 12}), work({16, 16, 16}));
  EXPECT_LT(work({2, 30, 90}), work({16, 16, 16}));
  EXPECT_GT(work({16, 16, 16}), 1e4);
}

// "auto" factorises small or thin grids and solves large ones by multigrid (where the
// build has it); the solver reports what it resolved to, and solves as that backend does.
TEST(PressureSolver, AutomaticChoosesByTheCostOfTheFactorisation) {
  const StaggeredGrid fluidisation(grid_of(Case{"", {4, 32, 2}, false, {P, I, P}, {P, O, P}}));
  const StaggeredGrid cube(grid_of(Case{"", {24, 24, 24}, false, {W, I, W}, {W, O, W}}));
  EXPECT_EQ(automatic_backend(fluidisation), PressureBackend::direct);
  EXPECT_EQ(automatic_backend(cube), multigrid_available() ? PressureBackend::multigrid : PressureBackend::direct);
  EXPECT_TRUE(direct_is_cheaper(256, 128, 50));
  EXPECT_FALSE(direct_is_cheaper(1e5, 1e3, 1e4));
  // hypre's loops run along its first axis, about twice as dear per cell on lines of 2
  // cells (bench/gas_poisson, 2 x 30 x 90: 4.6 ms in lines along x, 2.4 ms along y): the
  // estimate charges each line; 5400 cells with W = 1208 in lines of 2 factorise, in
  // lines of 90 go to multigrid.
  EXPECT_TRUE(direct_is_cheaper(5400, 2700, 1208));
  EXPECT_FALSE(direct_is_cheaper(5400, 60, 1208));
  // The multigrid backend runs along the longer of x and y, so Goldschmidt's grid
  // (x 2, y 30) goes to multigrid, its lines 30 long.
  const StaggeredGrid goldschmidt(grid_of(Case{"", {2, 30, 90}, false, {W, W, I}, {W, W, O}}));
  EXPECT_EQ(automatic_backend(goldschmidt), multigrid_available() ? PressureBackend::multigrid : PressureBackend::direct);
  PressureSolver a(fluidisation, {}), direct(fluidisation, [] {
    PressureSolverSpec s;
    s.backend = PressureBackend::direct;
    return s;
  }());
  EXPECT_EQ(a.backend(), PressureBackend::direct);
  const Problem p = random_problem(fluidisation, 5);
  const std::array<const std::vector<double>*, 3> d{&p.d[0], &p.d[1], &p.d[2]};
  std::vector<double> b1 = p.b, b2 = p.b, phi1(fluidisation.cell_count(), 0.0), phi2 = phi1;
  a.solve(d, b1, phi1);
  direct.solve(d, b2, phi2);
  EXPECT_EQ(phi1, phi2);
  EXPECT_NE(PressureSolver(cube, {}).backend(), PressureBackend::automatic);
}

}  // namespace
