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
/// (a particle with K = 0, or one gone through an outlet), its difference waits for the
/// next gas step (saved in checkpoints).
///
/// Among MPI processes that share the gas's planes (TwoWayExchange::share_planes), each
/// adds up K and K v on its reach of planes only, works on the grid's window (its reach)
/// and counts its own planes in the balance; a difference waiting is its cell's owner's,
/// sent to the processes whose reach holds it where any is waiting.
/// The particles' share is explicit in the new gas velocity: stable while Δt stays below
/// about 2 m/K, the particles' own relaxation time (ε_s ρ_p/(ε_g ρ_g) times the gas's).
#include <utility>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/coupling/deposition.hpp"
#include "cdm/solver/coupling/two_way_exchange.hpp"
#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/fluid/gas_field.hpp"
#include "cdm/solver/fluid/gas_solver.hpp"
#include "cdm/solver/particle_store.hpp"

namespace cdm::coupling {

class ImplicitDrag {
 public:
  /// With @p exchange's deposition and its planes (TwoWayExchange::share_planes).
  ImplicitDrag(const fluid::StaggeredGrid& grid, const TwoWayExchange& exchange);

  /// Before the gas step, with the particles' reaction of the step still gathered in
  /// the exchange: β and β V_s on the faces of @p gs (its drag_* and drag_target_*) from
  /// the particles' drag coefficients K (ParticleStore::drag_k), velocities and positions.
  /// Among MPI ranks (@p ranks) each deposits its own particles, in sums whose result
  /// does not depend on their order (exact_sums.hpp), added up: the same cells on any
  /// number of ranks, without gathering the particles (a collective call).
  void prepare(const ParticleStore& p, fluid::GasSolver& gs, RankSplit* ranks = nullptr);
  /// After the gas step of @p dtg: the particles receive the difference between what the
  /// gas took and their own impulse (each rank its own particles); returns, to add to the
  /// exchange's balance, the particles' kick (summed as prepare's deposits are) and the
  /// gas's momentum less the −J the exchange recorded [N s].
  CouplingBalance give_back(ParticleStore& p, const fluid::GasField& gas, const fluid::GasSolver& gs, double dtg,
                            RankSplit* ranks = nullptr);

  /// The differences kept for the next gas step [N s] (cells without particles; among
  /// processes each plane from its owner: OutArchive::put_planes()).
  void save_state(OutArchive& a) const;
  void load_state(InArchive& a);

 private:
  /// Whether the processes share the planes, each keeping its reach (alike on all).
  bool divided() const { return !exchange_.held_whole(); }
  /// The planes along z this process counts in the balance: its own where divided().
  std::pair<int, int> counted_planes() const;
  /// Zero the cells beyond the grid's window, their memory returned to the system
  /// (StaggeredGrid::zero_outside_window), where the window moved since the last time.
  void zero_outside_window();

  const fluid::StaggeredGrid& grid_;
  const TwoWayExchange& exchange_;
  const Deposition& deposition_;
  ExactSums k_sums_, kv_sums_;   // prepare's deposits of K and K v, zero between gas steps
  std::vector<double> k_cell_;   // Σ w K per cell [kg/s]
  std::vector<double> kv_[3];    // Σ w K v per cell [N]
  std::vector<double> diff_[3];  // −J_c (the reaction gathered), then the difference per cell [N s]
  std::vector<double> pending_[3];  // differences of cells without particles, for the next step [N s]
  std::pair<std::size_t, std::size_t> pending_span_{0, 0};  // the flat range where pending_ may be nonzero
  bool pending_any_ = false;  // some cell's pending_ is nonzero (alike on every process)
  std::size_t zeroed_at_ = 0;  // the grid's window_moves() at the last zero_outside_window()
  Vec3 gathered_;                   // Σ −J_c of the step [N s]
  double k_max_ = 0.0;              // the largest K at prepare() [kg/s]
};

}  // namespace cdm::coupling
