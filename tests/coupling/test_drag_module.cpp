// The drag and pressure-gradient modules evaluated once per gas step: with the drag
// module taking the pressure gradient (one evaluation from shared interpolation stencils,
// one pass per step), every particle's force and drag force are the same to the bit as
// the two modules' own evaluations and passes give, at the evaluating step and after it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cdm/solver/coupling/drag_module.hpp"
#include "cdm/solver/coupling/two_way_exchange.hpp"
#include "cdm/solver/fluid/gas_field.hpp"
#include "cdm/solver/particle_store.hpp"

namespace {

using namespace cdm;
using namespace cdm::coupling;
using namespace cdm::fluid;

GasSpec gas_spec() {
  GasSpec s;
  GridSpec& g = s.grid;
  g.lo = {0.0, 0.0, 0.0};
  g.hi = {0.02, 0.04, 0.01};
  g.cells = {6, 12, 3};
  for (int f = 0; f < 6; ++f) g.faces[f].kind = BoundaryKind::no_slip;
  s.density = 1.2;
  s.viscosity = 1.8e-5;
  s.interpolation = InterpolationScheme::trilinear;
  return s;
}

/// A gas with smooth, nonzero velocity, pressure and void fraction everywhere.
void fill(GasField& gas) {
  const StaggeredGrid& g = gas.grid();
  for (std::size_t i = 0; i < gas.u.size(); ++i) {
    const double x = static_cast<double>(i);
    gas.u[i] = 0.1 * std::sin(0.37 * x);
    gas.v[i] = 0.5 + 0.2 * std::cos(0.21 * x);
    gas.w[i] = 0.05 * std::sin(0.13 * x);
  }
  for (int k = -1; k <= g.n(2); ++k)
    for (int j = -1; j <= g.n(1); ++j)
      for (int i = -1; i <= g.n(0); ++i) {
        gas.p[g.at(i, j, k)] = 30.0 - 700.0 * (j + 0.5) * g.h(1) + 5.0 * std::sin(0.9 * i + 0.4 * k);
        gas.eps_g[g.at(i, j, k)] = 0.6 + 0.3 * std::cos(0.5 * i + 0.3 * j + 0.7 * k) * 0.5;
      }
  gas.refresh();
}

void add_particles(ParticleStore& p, const StaggeredGrid& g) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int n = 0; n < 200; ++n) {
    const Vec3 x{g.lo(0) + u01(rng) * g.length(0), g.lo(1) + u01(rng) * g.length(1), g.lo(2) + u01(rng) * g.length(2)};
    const Vec3 v{0.1 * (u01(rng) - 0.5), 0.3 * (u01(rng) - 0.5), 0.1 * (u01(rng) - 0.5)};
    p.add(x, v, 2.0e-4 * (1.0 + 0.2 * u01(rng)), 2500.0, 0);
  }
  p.enable_two_way();
}

/// With and without a two-way deposition kernel (which the pressure force then uses).
class TakenGradient : public ::testing::TestWithParam<bool> {};

TEST_P(TakenGradient, GivesTheSameForcesToTheBit) {
  GasField gas(gas_spec(), Vec3{0.0, -9.81, 0.0}, true, true);
  gas.enable_cell_pressure_gradient();
  fill(gas);
  const Deposition deposition(gas.grid(), Kernel::trilinear, 0.0);
  const Deposition* kernel = GetParam() ? &deposition : nullptr;
  ParticleStore separate, taken, drag_only;
  add_particles(separate, gas.grid());
  add_particles(taken, gas.grid());
  add_particles(drag_only, gas.grid());
  auto make_drag = [&] {
    return DragModule(gas, DragLaw::gidaspow, DragUpdate::explicit_force, 0.0, CouplingMethod::interpolate, kernel,
                      true);
  };
  GasStepClock clock_a, clock_b, clock_c;
  DragModule drag_a = make_drag(), drag_b = make_drag(), drag_c = make_drag();
  PressureGradientModule grad_a(gas, kernel), grad_b(gas, kernel);
  drag_a.evaluate_per_gas_step(clock_a);
  grad_a.evaluate_per_gas_step(clock_a);
  drag_b.evaluate_per_gas_step(clock_b);
  grad_b.evaluate_per_gas_step(clock_b);
  drag_b.take_pressure_gradient(grad_b);
  drag_c.evaluate_per_gas_step(clock_c);
  // Three force evaluations: the first evaluates the gas at the particles, the next two
  // apply the cached values with the particles' changed velocities.
  for (int step = 0; step < 3; ++step) {
    for (ParticleStore* p : {&separate, &taken, &drag_only})
      for (std::size_t i = 0; i < p->size(); ++i) {
        // Forces of the drag's and the pressure gradient's size, so that the order of the
        // sums shows in the last bits.
        const double s = std::sin(static_cast<double>(i + step));
        p->fx[i] = 3e-8 * s; p->fy[i] = -2e-8 * s; p->fz[i] = 1e-8 * s;
        p->vx[i] += 0.01 * step; p->vy[i] -= 0.02 * step;
      }
    drag_a.add_forces(separate, 1e-5);
    grad_a.add_forces(separate, 1e-5);
    drag_b.add_forces(taken, 1e-5);
    grad_b.add_forces(taken, 1e-5);
    drag_c.add_forces(drag_only, 1e-5);
    clock_a.due = clock_b.due = clock_c.due = false;
    for (std::size_t i = 0; i < separate.size(); ++i) {
      ASSERT_EQ(separate.fx[i], taken.fx[i]) << "step " << step << ", particle " << i;
      ASSERT_EQ(separate.fy[i], taken.fy[i]) << "step " << step << ", particle " << i;
      ASSERT_EQ(separate.fz[i], taken.fz[i]) << "step " << step << ", particle " << i;
      ASSERT_EQ(separate.dfx[i], taken.dfx[i]) << "step " << step << ", particle " << i;
      ASSERT_EQ(separate.dfy[i], taken.dfy[i]) << "step " << step << ", particle " << i;
      ASSERT_EQ(separate.dfz[i], taken.dfz[i]) << "step " << step << ", particle " << i;
      // The pressure gradient did act (the same drag without it leaves another force).
      ASSERT_NE(drag_only.fy[i], taken.fy[i]) << "step " << step << ", particle " << i;
      ASSERT_EQ(drag_only.dfy[i], taken.dfy[i]) << "step " << step << ", particle " << i;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(DragModule, TakenGradient, ::testing::Bool());

/// With two-way coupling the particles' pressure forces add up to what the gas's faces
/// leave to the solids, Σ_f (1 − ε_f) V_f ∂p_f (V_f half a cell on a boundary face), ε_g
/// deposited with the same kernel: for every kernel, to round-off. The face gradient
/// interpolated to the particles does not (checked, so that the test can fail).
TEST(PressureGradient, TwoWayParticlesTakeWhatTheFacesLeaveThem) {
  GasField gas(gas_spec(), Vec3{0.0, -9.81, 0.0}, true, true);
  gas.enable_cell_pressure_gradient();
  fill(gas);
  const StaggeredGrid& g = gas.grid();
  // A gradient that varies along y too, as across a bed's surface.
  for (int k = 0; k < g.n(2); ++k)
    for (int j = 0; j < g.n(1); ++j)
      for (int i = 0; i < g.n(0); ++i) gas.p[g.at(i, j, k)] += 40.0 * std::sin(1.3 * j);
  ParticleStore p;
  add_particles(p, g);
  for (const auto& [kernel, width] : {std::pair{Kernel::cell, 0.0}, std::pair{Kernel::trilinear, 0.0},
                                      std::pair{Kernel::gaussian, 2.5e-3}}) {
    TwoWayExchange exchange(g, true, kernel, width);
    exchange.deposit_void_fraction(p, gas.eps_g, 0.0);
    gas.refresh();
    Vec3 particles, interpolated, faces;
    for (std::size_t i = 0; i < p.size(); ++i) {
      particles += p.volume(i) * particle_pressure_gradient(gas, exchange.deposition(), p.position(i));
      interpolated += p.volume(i) * gas.pressure_gradient_at(p.position(i));
    }
    double* const sum[3] = {&faces.x, &faces.y, &faces.z};
    const std::vector<double>* grad[3] = {&gas.gpx, &gas.gpy, &gas.gpz};
    for (int a = 0; a < 3; ++a) {
      const auto s = static_cast<Staggering>(a);
      for (int k = 0; k < g.samples(s, 2); ++k)
        for (int j = 0; j < g.samples(s, 1); ++j)
          for (int i = 0; i < g.samples(s, 0); ++i) {
            int lo[3] = {i, j, k}, hi[3] = {i, j, k};
            lo[a] = std::max(lo[a] - 1, 0);
            hi[a] = std::min(hi[a], g.n(a) - 1);
            const bool boundary = lo[a] == hi[a];
            const double solids = 1.0 - 0.5 * (gas.eps_g[g.at(lo[0], lo[1], lo[2])] + gas.eps_g[g.at(hi[0], hi[1], hi[2])]);
            *sum[a] += (boundary ? 0.5 : 1.0) * g.cell_volume() * solids * (*grad[a])[g.at(i, j, k)];
          }
    }
    const double scale = std::abs(faces.y);
    EXPECT_NEAR(particles.x, faces.x, 1e-12 * scale) << to_string(kernel);
    EXPECT_NEAR(particles.y, faces.y, 1e-12 * scale) << to_string(kernel);
    EXPECT_NEAR(particles.z, faces.z, 1e-12 * scale) << to_string(kernel);
    EXPECT_GT(std::abs(interpolated.y - faces.y), 1e-6 * scale) << to_string(kernel);
  }
}

TEST(DragModule, TakingThePressureGradientNeedsBothOnOneClockAndTheExplicitDrag) {
  GasField gas(gas_spec(), Vec3{0.0, -9.81, 0.0}, true, true);
  GasStepClock clock, other;
  DragModule relaxed(gas, DragLaw::gidaspow, DragUpdate::implicit, 0.0);
  PressureGradientModule grad(gas);
  relaxed.evaluate_per_gas_step(clock);
  grad.evaluate_per_gas_step(clock);
  EXPECT_THROW(relaxed.take_pressure_gradient(grad), std::logic_error);
  DragModule every_step(gas, DragLaw::gidaspow, DragUpdate::explicit_force, 0.0);
  EXPECT_THROW(every_step.take_pressure_gradient(grad), std::logic_error);
  DragModule elsewhere(gas, DragLaw::gidaspow, DragUpdate::explicit_force, 0.0);
  elsewhere.evaluate_per_gas_step(other);
  EXPECT_THROW(elsewhere.take_pressure_gradient(grad), std::logic_error);
}

}  // namespace
