#pragma once
/// @file implicit_drag.hpp
/// @brief The interphase drag treated implicitly in the gas momentum equation, with the
/// momentum exchanged kept equal and opposite to round-off.
///
/// The particles take their drag K(u_g − v) over the particle sub-steps of a gas step with
/// the gas velocity u^n of its start; each particle's impulse J_i is gathered over the gas
/// step and deposited on the cells at the gas step (two_way_exchange.hpp), with the same
/// weights as its K. With the implicit treatment the gas does not take −J
/// explicitly: it feels −β(u^{n+1} − V_s), β = Σ_i w K_i / V the particles' drag
/// coefficients deposited with the coupling kernel and β V_s = Σ_i w K_i v_i / V their
/// momentum-weighted velocities at the end of the particle sub-steps, both handed from the
/// cells to the faces as the force is (half to each face); the gas step is then stable at any
/// Δt β/(ε ρ) (MFIX's partial elimination, CFDEM's semi-implicit K_sl split).
///
/// The momentum this gives the gas, G_c = −K_c Δt (ū_c^{n+1} − V̄_c) per cell (K_c = Σ w K,
/// ū_c the mean of the cell's two new face velocities, V̄_c = Σ w K v / K_c),
/// differs from −J_c. The difference goes to the particles at the end of the gas step:
/// particle i receives Σ_c (w_ic K_i/K_c)(−G_c − J_c), so that what the particles receive
/// is what the gas gives to round-off every gas step (each particle keeps its own drag
/// impulse less its share of the cell's, plus its share of the cell's implicit drag). J
/// and K are deposited with the same weights, so a cell without K holds no J; were one to
/// (a particle with K = 0), its difference waits for the next gas step (pending(), saved
/// in checkpoints).
/// The particles' share is explicit in the new gas velocity: stable while Δt stays below
/// about 2 m/K, the particles' own relaxation time (ε_s ρ_p/(ε_g ρ_g) times the gas's).
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/coupling/deposition.hpp"
#include "cdm/solver/coupling/two_way_exchange.hpp"
#include "cdm/solver/fluid/gas_field.hpp"
#include "cdm/solver/fluid/gas_solver.hpp"
#include "cdm/solver/particle_store.hpp"

namespace cdm::coupling {

class ImplicitDrag {
 public:
  ImplicitDrag(const fluid::StaggeredGrid& grid, const Deposition& deposition);

  /// Before the gas step, with the particles' reaction of the step still gathered in
  /// @p exchange: β and β V_s on the faces of @p gs (its drag_* and drag_target_*) from
  /// the particles' drag coefficients K (ParticleStore::drag_k), velocities and positions.
  /// Among MPI ranks (@p ranks) each deposits its own particles, in sums whose result
  /// does not depend on their order (exact_sums.hpp), added up: the same cells on any
  /// number of ranks, without gathering the particles (a collective call).
  void prepare(const ParticleStore& p, const TwoWayExchange& exchange, fluid::GasSolver& gs,
               RankSplit* ranks = nullptr);
  /// After the gas step of @p dtg: the particles receive the difference between what the
  /// gas took and their own impulse (each rank its own particles); returns, to add to the
  /// exchange's balance, the particles' kick (summed as prepare's deposits are) and the
  /// gas's momentum less the −J the exchange recorded [N s].
  CouplingBalance give_back(ParticleStore& p, const fluid::GasField& gas, const fluid::GasSolver& gs, double dtg,
                            RankSplit* ranks = nullptr);

  /// The difference kept for the next gas step (cells without particles) [N s], and
  /// its checkpoint.
  Vec3 pending() const;
  void save_state(OutArchive& a) const;
  void load_state(InArchive& a);

 private:
  const fluid::StaggeredGrid& grid_;
  const Deposition& deposition_;
  std::vector<double> k_cell_;   // Σ w K per cell [kg/s]
  std::vector<double> kv_[3];    // Σ w K v per cell [N]
  std::vector<double> diff_[3];  // −J_c (the reaction gathered), then the difference per cell [N s]
  std::vector<double> pending_[3];  // differences of cells without particles, for the next step [N s]
  Vec3 gathered_;                   // Σ −J_c of the step [N s]
  double k_max_ = 0.0;              // the largest K at prepare() [kg/s]
};

}  // namespace cdm::coupling
