/// @file fluidization.cpp
/// @brief Fluidisation: a settled bed under inflow raised in steps. The frictional
/// pressure drop across the bed, against the buoyant weight per area once fluidised (the
/// plateau), and the minimum-fluidisation velocity where the packed-bed branch meets it,
/// against the same drag law's U_mf at the settled bed's gas fraction.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "cdm/oracles/packed_bed.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

namespace {

/// The inflows, as multiples of the oracle's U_mf: three packed, three fluidised.
const std::vector<double> kFactors = {0.25, 0.5, 0.75, 1.25, 1.5, 2.0};

/// The settled bed: height H from the particles' mean height (uniform bed: H = 2 (ȳ −
/// floor)), its mean gas fraction, and its bulk gas fraction away from its ends (the
/// layer against the distributor is looser, the top ragged): the spheres' exact volume in
/// the slab [floor + d, floor + H − d], by spherical caps.
struct SettledBed {
  double H, eps_bed, eps_bulk;
};

SettledBed settled_bed(const ParticleStore& p, double vol, double area, double floor_y, double d_p) {
  double ybar = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) ybar += p.y[i];
  ybar /= static_cast<double>(p.size());
  const double H = 2.0 * (ybar - floor_y), eps_bed = 1.0 - vol / (area * H);
  auto cap = [](double r, double h) {  // volume of a sphere of radius r below height h above its bottom
    h = std::clamp(h, 0.0, 2.0 * r);
    return std::numbers::pi * h * h * (3.0 * r - h) / 3.0;
  };
  const double s_lo = floor_y + d_p, s_hi = floor_y + H - d_p;
  double v_slab = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = p.radius[i], bottom = p.y[i] - r;
    v_slab += cap(r, s_hi - bottom) - cap(r, s_lo - bottom);
  }
  return {H, eps_bed, 1.0 - v_slab / (area * (s_hi - s_lo))};
}

/// Per inflow: the mean frictional pressure drop, the same corrected by the bed's momentum
/// change, and its fluctuation; the same drop between cell centres and the gas's force on
/// the bed per area less its buoyancy; and every 10th gas step, the history.
struct Segments {
  std::vector<double> U, dP, dP_corr, dP_sd, dP_centre, force, face_force, wall_force, hist_t, hist_u, hist_dp, hist_mv;
};

/// What the comparison found besides its measurements: the measured U_mf and the oracle's
/// parameters at the bed's bulk gas fraction.
struct Fluidised {
  double umf;
  oracles::BedParams bulk;
};

/// The measured branch against the oracles: adds the measurements to @p r.
Fluidised compare(const Segments& seg, const SettledBed& bed, double weight, const oracles::BedParams& bp,
                  const oracles::MinFluidisation& mf, RunOutput& r) {
  const auto& U = seg.U;
  const auto& dP = seg.dP;
  const double H = bed.H;
  // Plateau: the fluidised segments (U >= 1.25 U_mf), each also reported on its own.
  double plateau = 0.0, plateau_raw = 0.0;
  int np = 0;
  for (std::size_t k = 0; k < U.size(); ++k)
    if (kFactors[k] > 1.0) {
      plateau += seg.dP_corr[k];
      plateau_raw += dP[k];
      ++np;
      char q[48];
      std::snprintf(q, sizeof q, "plateau_%.2fUmf", kFactors[k]);
      r.measurements.push_back({q, "rel_pct_vs_weight", rel_pct(weight, seg.dP_corr[k])});
      r.measurements.push_back({q, "uncorrected_rel_pct_vs_weight", rel_pct(weight, dP[k])});
    }
  plateau /= np;
  plateau_raw /= np;
  r.measurements.push_back({"plateau", "uncorrected_rel_pct_vs_weight", rel_pct(weight, plateau_raw)});
  // The packed branch against Ergun at the bed's mean and at its bulk gas fraction.
  oracles::BedParams bulk = bp;
  bulk.eps_g = bed.eps_bulk;
  double dev_mean = 0.0, dev_bulk = 0.0;
  for (std::size_t k = 0; k < U.size(); ++k)
    if (kFactors[k] < 1.0) {
      dev_mean = std::max(dev_mean, rel_pct(oracles::ergun_pressure_gradient(bp, U[k]) * H, dP[k]));
      dev_bulk = std::max(dev_bulk, rel_pct(oracles::ergun_pressure_gradient(bulk, U[k]) * H, dP[k]));
    }
  r.measurements.push_back({"packed_dP", "max_rel_pct_vs_ergun_eps_bed", dev_mean});
  r.measurements.push_back({"packed_dP", "max_rel_pct_vs_ergun_eps_bulk", dev_bulk});
  // The packed bed's momentum balance: the gas's force on it (drag and pressure-gradient
  // force less buoyancy) against the pressure drop from the inlet face times the area.
  double dev_force = 0.0;
  for (std::size_t k = 0; k < U.size(); ++k)
    if (kFactors[k] < 1.0) dev_force = std::max(dev_force, rel_pct(dP[k], seg.force[k]));
  r.measurements.push_back({"packed_gas_force", "max_rel_pct_vs_dP", dev_force});
  // The bed's momentum balance on every inflow: what the gas carries (the pressure drop,
  // less the momentum the bed gained) and what the walls carry (their measured contact
  // force) against the buoyant weight.
  double dev_balance = 0.0;
  for (std::size_t k = 0; k < U.size(); ++k)
    dev_balance = std::max(dev_balance, rel_pct(weight, seg.dP_corr[k] + seg.wall_force[k]));
  r.measurements.push_back({"bed_momentum_balance", "max_rel_pct_vs_weight", dev_balance});
  // Packed branch: least-squares dP = a U + b U^2 through the packed segments, met with
  // the measured plateau.
  double s11 = 0, s12 = 0, s22 = 0, r1 = 0, r2 = 0;
  for (std::size_t k = 0; k < U.size(); ++k)
    if (kFactors[k] < 1.0) {
      const double x1 = U[k], x2 = U[k] * U[k];
      s11 += x1 * x1; s12 += x1 * x2; s22 += x2 * x2; r1 += x1 * dP[k]; r2 += x2 * dP[k];
    }
  const double det = s11 * s22 - s12 * s12, a = (r1 * s22 - r2 * s12) / det, b = (s11 * r2 - s12 * r1) / det;
  const double umf = b != 0.0 ? (-a + std::sqrt(a * a + 4.0 * b * plateau)) / (2.0 * b) : plateau / a;
  r.measurements.push_back({"plateau", "rel_pct_vs_weight", rel_pct(weight, plateau)});
  r.measurements.push_back({"u_mf", "rel_pct_vs_drag_law", rel_pct(mf.U, umf)});
  const oracles::MinFluidisation mf_bulk = oracles::minimum_fluidisation(bulk);
  r.measurements.push_back({"u_mf", "rel_pct_vs_drag_law_eps_bulk", rel_pct(mf_bulk.U, umf)});
  r.measurements.push_back({"u_mf", "rel_pct_vs_wen_yu_1966", rel_pct(oracles::wen_yu_minimum_fluidisation_estimate(bp), umf)});
  return {umf, bulk};
}

}  // namespace

RunOutput fluidization(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  SceneSpec spec = scene_for(v, rc);
  // Each inflow is held for t_segment (packed) or t_fluidised (fluidised: the bed's
  // pressure drop fluctuates as it bubbles, so it is averaged longer); the first
  // t_transient of each is discarded and the rest averaged.
  const double t_settle = v.param("t_settle"), t_seg = v.param("t_segment"), t_fl = v.param("t_fluidised"),
               t_tr = v.param("t_transient");
  auto hold = [&](double f) { return f < 1.0 ? t_seg : t_fl; };
  spec.end_time = t_settle + spec.dt;
  for (double f : kFactors) spec.end_time += hold(f);
  Simulation sim(spec);
  fluid::GasField& gas = *sim.gas_mutable();
  const fluid::StaggeredGrid& g = gas.grid();
  const ParticleStore& p = sim.particles();
  const double area = g.length(0) * g.length(2), floor_y = v.param("floor");
  const double vol = solids_volume(p);
  const double rho_g = gas.density(), grav = v.param("g");
  const double weight = vol * (v.param("rho_p") - rho_g) * grav / area;  // buoyant weight per area [Pa]
  auto layer_p = [&](int j) {
    double s = 0.0;
    for (int k = 0; k < g.n(2); ++k)
      for (int i = 0; i < g.n(0); ++i) s += gas.p[g.at(i, j, k)];
    return s / (g.n(0) * g.n(2));
  };
  // Frictional pressure drop from the inlet face (the mean of the first cell centre and
  // the solver's pressure ghost below it: the pressure the particles on the distributor
  // feel) to the top cell centre, less the gas's own hydrostatic head
  // over that height; the same from the first cell centre (the bed less its lowest half
  // cell); the gas's force on the bed per area, less its buoyancy.
  const int j_hi = g.n(1) - 1;
  const double dy = (j_hi + 0.5) * g.h(1);
  auto frictional = [&] {
    const double p_in = 0.5 * (layer_p(-1) + layer_p(0));
    return p_in - layer_p(j_hi) - rho_g * grav * dy;
  };
  auto frictional_centre = [&] { return layer_p(0) - layer_p(j_hi) - rho_g * grav * (dy - 0.5 * g.h(1)); };
  auto bed_force = [&] { return (gas_force_y(p, gas, sim.deposition()) - vol * rho_g * grav) / area; };
  // The walls' contact force on the bed along y per area: the distributor's and the
  // lid's normal forces (their friction, if any, acts along them, not along y).
  ContactModule& contacts = *sim.contact();
  contacts.set_recording(true);
  auto walls_force = [&] {
    const std::vector<double>& fn = contacts.wall_normal_force();
    const std::vector<Wall>& walls = contacts.walls();
    const std::vector<std::uint32_t>& wall_of = contacts.list().wall_ids();  // per entry of fn
    double f = 0.0;
    for (std::size_t q = 0; q < fn.size(); ++q)
      if (fn[q] > 0.0) f += fn[q] * walls[wall_of[q]].normal.y;
    return f / area;
  };
  // The same with the pressure-gradient part as the gas's faces hold it: the solids
  // fraction 1 − ε_f of each y-face (as the gas equations average it; a boundary face
  // takes its cell's) times its gradient over its volume (a boundary face's half cell).
  // The particles feel the gradient interpolated to their centres instead; the two sums
  // differ by how the interpolation and the deposition kernels see the bed.
  auto bed_force_on_faces = [&] {
    double f = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) f += p.dfy[i];
    const int ny = g.n(1);
    for (int k = 0; k < g.n(2); ++k)
      for (int j = 0; j <= ny; ++j)
        for (int i = 0; i < g.n(0); ++i) {
          const double below = gas.eps_g[g.at(i, std::max(j - 1, 0), k)], above = gas.eps_g[g.at(i, std::min(j, ny - 1), k)];
          const double share = j == 0 || j == ny ? 0.5 : 1.0;
          f -= share * g.cell_volume() * (1.0 - 0.5 * (below + above)) * gas.gpy[g.at(i, j, k)];
        }
    return (f - vol * rho_g * grav) / area;
  };
  const Stopwatch clock;
  auto advance = [&](double until) {
    while (sim.time() < until - 0.5 * sim.dt()) sim.step();
  };
  advance(t_settle);
  const SettledBed bed = settled_bed(p, vol, area, floor_y, v.param("d"));
  oracles::BedParams bp;
  bp.law = oracles::DragLaw::Gidaspow;
  set_particle_gas(bp, v);
  bp.g = grav;
  bp.eps_g = bed.eps_bed;
  const oracles::MinFluidisation mf = oracles::minimum_fluidisation(bp);
  Segments seg;
  for (double f : kFactors) {
    const double u = f * mf.U;
    gas.set_inlet_velocity(2, u);
    const double start = sim.time(), end = start + hold(f);
    double s = 0.0, s2 = 0.0, s_centre = 0.0, s_force = 0.0, s_faces = 0.0, s_walls = 0.0, t_a = 0.0, t_b = 0.0, mv_a = 0.0;
    int n = 0;
    std::uint64_t n_walls = 0;
    while (sim.time() < end - 0.5 * sim.dt()) {
      sim.step();
      // The contacts change within a gas step: the walls' force is averaged every step.
      if (sim.time() >= start + t_tr) { s_walls += walls_force(); ++n_walls; }
      if (sim.steps() % sim.substeps() != 0) continue;  // once per gas step
      const double q = frictional();
      if (sim.steps() % (10 * sim.substeps()) == 0) {
        seg.hist_t.push_back(sim.time()); seg.hist_u.push_back(u); seg.hist_dp.push_back(q);
        seg.hist_mv.push_back(momentum_y(p) / area);
      }
      if (sim.time() < start + t_tr) continue;
      if (n == 0) { t_a = sim.time(); mv_a = momentum_y(p); }
      s += q; s2 += q * q; ++n;
      s_centre += frictional_centre();
      s_force += bed_force();
      s_faces += bed_force_on_faces();
      t_b = sim.time();
    }
    const double mv_b = momentum_y(p);
    seg.U.push_back(u);
    seg.dP.push_back(s / n);
    // The bed's momentum balance over the window: mean gas force on it = weight +
    // Δ(Σ m v_y)/T (+ contact forces from the walls, zero once it is fluidised). A bubbling
    // bed's pressure drop swings by ~15 %, with correlation times of ~30 ms, so a 0.45 s
    // mean of it is uncertain by a few per cent; subtracting the momentum the bed gained
    // over the same window removes that sampling error (a bounded momentum over a finite
    // window), leaving what the time average converges to.
    seg.dP_corr.push_back(s / n - (mv_b - mv_a) / (area * std::max(t_b - t_a, sim.dt())));
    seg.dP_sd.push_back(std::sqrt(std::max(0.0, s2 / n - (s / n) * (s / n))));
    seg.dP_centre.push_back(s_centre / n);
    seg.force.push_back(s_force / n);
    seg.face_force.push_back(s_faces / n);
    seg.wall_force.push_back(s_walls / static_cast<double>(std::max<std::uint64_t>(n_walls, 1)));
  }
  RunOutput r = run_output(sim, clock.seconds());
  if (rc.timing_only) return r;
  r.oracle_accuracy = accuracy_text(mf.accuracy);
  const auto [umf, bulk] = compare(seg, bed, weight, bp, mf, r);
  if (rc.series_path.empty()) return r;
  {
    TableWriter w(rc.series_path,
                  {"U[m/s]", "dP_frictional[Pa]", "dP_momentum_corrected[Pa]", "dP_std_dev[Pa]",
                   "dP_from_cell_centre[Pa]", "gas_force_on_bed_per_area[Pa]",
                   "gas_force_on_bed_faces_per_area[Pa]", "wall_force_on_bed_per_area[Pa]",
                   "buoyant_weight_per_area[Pa]", "U_mf_oracle[m/s]", "dP_ergun_at_eps_bed[Pa]",
                   "dP_ergun_at_eps_bulk[Pa]"},
                  {"fluidisation " + v.name + ", " + rc.integrator + ": settled bed height " + std::to_string(bed.H) +
                       " m, gas fraction " + std::to_string(bed.eps_bed) + " (bulk, between d and H - d: " +
                       std::to_string(bed.eps_bulk) + "); measured U_mf " + std::to_string(umf) + " m/s",
                   "dP averaged over each inflow after the first " + std::to_string(t_tr) +
                       " s; std_dev = its fluctuation (not an error bar of the mean)"});
    for (std::size_t k = 0; k < seg.U.size(); ++k)
      w.row({seg.U[k], seg.dP[k], seg.dP_corr[k], seg.dP_sd[k], seg.dP_centre[k], seg.force[k], seg.face_force[k],
             seg.wall_force[k], weight, mf.U,
             oracles::ergun_pressure_gradient(bp, seg.U[k]) * bed.H, oracles::ergun_pressure_gradient(bulk, seg.U[k]) * bed.H});
  }
  TableWriter h(series_beside(rc.series_path, "_history"),
                {"t[s]", "U[m/s]", "dP_frictional[Pa]", "buoyant_weight_per_area[Pa]", "bed_momentum_per_area[Pa*s]"},
                {"fluidisation " + v.name + ": frictional pressure drop every 10th gas step while the inflow is raised"});
  for (std::size_t k = 0; k < seg.hist_t.size(); ++k)
    h.row({seg.hist_t[k], seg.hist_u[k], seg.hist_dp[k], weight, seg.hist_mv[k]});
  return r;
}

}  // namespace cdm::verification::runners
