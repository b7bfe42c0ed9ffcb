#pragma once
/// @file two_way_exchange.hpp
/// @brief What the particles give the solved gas: the volume they take from it (the gas
/// fraction ε_g on the cells) and the reaction to the drag on them, gathered over the
/// particle sub-steps of a gas step and handed to the gas as a force on its faces, with
/// the balance of the momentum exchanged.
#include <memory>
#include <utility>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/coupling/deposition.hpp"
#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/fluid/gas_solver.hpp"
#include "cdm/solver/fluid/staggered_grid.hpp"
#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/vec3.hpp"

namespace cdm {
class RankSplit;
}

namespace cdm::coupling {

/// Momentum exchanged through drag over a gas step [N s]: what the particles received
/// and what the gas received, on the cells, then on the faces of the grid (each cell
/// hands half of its value along a component to each of its two faces; the share of a
/// face whose velocity is fixed, a wall or an inlet, is taken there, not by the gas
/// equations: GasField::drag_gradient).
struct CouplingBalance {
  Vec3 particles, gas_cells, gas_faces;
};

/// Built for every solved gas; with @c two_way false it holds nothing and gives nothing
/// (the gas keeps its own ε_g).
class TwoWayExchange {
 public:
  /// @p kernel and @p width: how a particle spreads over the cells (deposition.hpp).
  TwoWayExchange(const fluid::StaggeredGrid& grid, bool two_way, Kernel kernel, double width);

  bool two_way() const { return deposition_ != nullptr; }
  /// The deposition kernel (nullptr without two-way coupling).
  const Deposition* deposition() const { return deposition_.get(); }

  /// ε_g on the cells from the particles' volumes, each cell's sum the same whatever the
  /// order of its terms (exact_sums.hpp); throws SimulationError, naming the cell and
  /// @p time, if a cell is packed beyond what the gas equations can take.
  /// Among MPI ranks (@p ranks, once the particles are dealt out) each deposits its own.
  void deposit_void_fraction(const ParticleStore& p, std::vector<double>& eps, double time,
                             RankSplit* ranks = nullptr);
  /// Move the particles' drag impulses (emptying their accumulators) onto the cells as
  /// the reaction on the gas, at every step: each cell's share of the step in a sum
  /// whose value does not depend on the order of its terms (exact_sums.hpp), added to
  /// the reaction gathered so far. Among MPI ranks (@p ranks, once the particles are
  /// dealt out) each rank deposits its own particles and the sums of the cells the
  /// step reached are added up over the ranks (or, where the particles are fewer than
  /// those cells, their positions and impulses are gathered and every rank deposits
  /// them all). Throws SimulationError, naming @p time, if an impulse is not finite.
  void deposit_impulses(ParticleStore& p, double time, RankSplit* ranks = nullptr);
  /// deposit_impulses and deposit_void_fraction at once, each particle's stencil
  /// computed once for both; the impulses' sums too the same whatever their order
  /// (exact_sums.hpp). Among MPI ranks (@p ranks, once the particles are dealt out)
  /// each rank deposits its own particles and the cells' sums are added up over the
  /// ranks: the same cells on any number of ranks, without the particles gathered.
  void deposit_impulses_and_void_fraction(ParticleStore& p, std::vector<double>& eps, double time,
                                          RankSplit* ranks = nullptr);
  /// The same for one particle leaving through an outlet before its gas step, at @p x
  /// with the impulse @p j accumulated so far: @p j spread about the point of the gas
  /// domain nearest to @p x.
  void deposit_impulse_of_leaving(Vec3 x, Vec3 j);
  /// The reaction gathered since the last gas step, as a force per unit volume over
  /// @p dtg on the faces of @p solver (added to what it holds); records the balance and
  /// starts gathering anew.
  void apply_reaction(fluid::GasSolver& solver, double dtg);
  /// The reaction on the gas gathered so far in the present gas step, per cell [N s]
  /// (component @p c).
  const std::vector<double>& reaction(int c) const { return c == 0 ? imp_x_ : c == 1 ? imp_y_ : imp_z_; }
  /// Add @p b (an implicit drag's share of the step, implicit_drag.hpp) to the balance
  /// of the last gas step.
  void add_to_balance(const CouplingBalance& b);
  /// The balance of the last gas step (zero without two-way coupling).
  const CouplingBalance& balance() const { return balance_; }

  /// Among MPI processes that divide the gas step by planes (@p planes; nullptr: none):
  /// where each process's particles deposit within its reach of planes
  /// (PlaneShare::set_reach), the cells' sums are added up on each process's reach only
  /// (PlaneShare::add_up), not on every cell; ε_g and the reaction are then valid there,
  /// and the gas fraction's check reads each process's own planes. The reaction and ε_g
  /// are then kept on the grid's window only (StaggeredGrid::set_window).
  void share_planes(const fluid::PlaneShare* planes) { planes_ = planes; }
  /// The planes shared (share_planes; nullptr: none).
  const fluid::PlaneShare* planes() const { return planes_; }
  /// Whether every process keeps every cell: alike on every process (the reaches are),
  /// so that the collectives it decides are (a window may be wider on the writer).
  bool held_whole() const { return !planes_ || planes_->reach_whole(grid_.n(2)); }
  /// Sums on the cells (@p blocks blocks of a sum a cell, then any totals).
  struct CellSums {
    ExactSums* sums;
    std::size_t blocks;
  };
  /// Each process's sums of its own particles' deposits (@p a, and @p b unless empty),
  /// added up over the processes (@p own; nothing without): on each process's reach of
  /// planes where every process's particles deposited within its own (share_planes),
  /// else on every cell; the totals on every process. Returns whether by planes.
  /// Collective.
  bool add_up_cells(const ParticleStore& p, RankSplit* own, CellSums a, CellSums b = {nullptr, 0}) const;
  /// Start @p s as @p n sums of the bounds given: where it holds n sums, zero since their
  /// last use (clear_sums), by setting the bounds only, without a pass over them.
  static void start_sums(ExactSums& s, std::size_t n, double bound, double sum_bound);
  /// Zero @p s (@p blocks blocks of a sum a cell, then any totals) after its use: where
  /// added up @p by_planes (add_up_cells), this process's reach only, the rest being zero;
  /// else deposited_span(@p own).
  void clear_sums(ExactSums& s, std::size_t blocks, bool by_planes, const RankSplit* own) const;
  /// The reaction gathered so far in the present gas step (where each process holds its
  /// reach only, each plane from its owner: OutArchive::put_planes()).
  void save_state(OutArchive& a) const;
  void load_state(InArchive& a);

 private:
  /// The largest impulse component of @p p's particles (each rank's own with @p own),
  /// over the ranks; throws SimulationError, naming @p time, if one is not finite.
  static double largest_impulse(const ParticleStore& p, RankSplit* own, double time);
  /// A particle's impulse @p j onto the cells about @p at.
  void deposit_impulse(Vec3 j, Vec3 at);
  /// The volumes of @p p's particles (over the cell volume) onto @p vol and, with
  /// @p imp, their impulses' reaction (per cell along x, y, z; then their total): each
  /// rank its own particles with @p own, the sums then added up over the ranks; each
  /// thread a range of them. The sums must be reset (their bounds) first.
  void deposit_sums(const ParticleStore& p, RankSplit* own, ExactSums* imp, ExactSums& vol) const;
  /// The planes of cells along z that the stencils of @p p's own particles reach (none:
  /// first > second; a position not finite: beyond the grid).
  std::pair<int, int> planes_reached(const ParticleStore& p, RankSplit& own) const;
  /// Zero the reaction's and the sums' cells beyond the grid's window, their memory
  /// returned to the system (StaggeredGrid::zero_outside_window), where the window moved
  /// since the last time.
  void zero_outside_window();
  /// The z plane of the padded cell index @p c.
  int plane_of(std::size_t c) const;
  /// The flat range of the cells whose reaction and ε_g are kept: the grid's window
  /// (every cell unless the planes are shared, or are to be: GasSolver::first_planes).
  std::pair<std::size_t, std::size_t> held_span() const;
  /// The flat range of the cells deposit_sums() adds to: every cell with @p own
  /// particles, else held_span().
  std::pair<std::size_t, std::size_t> deposited_span(const RankSplit* own) const;
  /// The reaction written (possibly nonzero) over @p span too: apply_reaction clears it.
  void touch(std::pair<std::size_t, std::size_t> span);
  /// Start @p vol for the volumes of @p p's particles (over the cell volume), each rank's
  /// own with @p own.
  void start_volume_sums(const ParticleStore& p, RankSplit* own, ExactSums& vol) const;
  /// @p eps = 1 − the solids fraction deposited in @p vol, checked (throws
  /// SimulationError naming the cell and @p time), its ghosts filled.
  void finish_void_fraction(const ExactSums& vol, std::vector<double>& eps, double time) const;

  const fluid::StaggeredGrid& grid_;
  const fluid::PlaneShare* planes_ = nullptr;  // share_planes
  bool reaction_whole_ = true;  // imp_* valid on every plane (else on this process's reach)
  std::unique_ptr<Deposition> deposition_;
  std::vector<double> imp_x_, imp_y_, imp_z_;  // drag reaction on the gas per cell [N s]
  std::pair<std::size_t, std::size_t> touched_{0, 0};  // the flat range where imp_* may be nonzero
  std::size_t zeroed_at_ = 0;  // the grid's window_moves() at the last zero_outside_window()
  ExactSums impulse_sums_;  // deposit_impulses_and_void_fraction's, zero between gas steps
  mutable ExactSums volume_sums_;  // and the deposits' volumes, zero between gas steps
  ExactSums step_sums_;  // deposit_impulses's: per cell x, y, z interleaved, then the total; zero between steps
  std::vector<std::uint8_t> reached_;         // deposit_impulses: 1 for a cell reached this step
  std::vector<std::uint32_t> reached_cells_;  // and those cells
  std::size_t reached_span_ = 0;              // the run of cells the last step reached
  mutable std::vector<ExactSums> partial_;  // deposit_sums's other threads' (impulses, volumes)
  Vec3 particle_impulse_;  // Σ drag impulse on the particles since the gas step began
  CouplingBalance balance_;
};

}  // namespace cdm::coupling
