#pragma once
/// @file gas_solver.hpp
/// @brief Volume-averaged incompressible gas on the staggered grid: Garg et al. (2012)
/// eqs 1–4 at constant gas density (MFIX "model A"), advanced by an incremental
/// pressure-correction (projection) method.
///
///   ∂ε/∂t + ∇·(ε u) = 0
///   ρ_g [∂(ε u)/∂t + ∇·(ε u u)] = −ε ∇p + ∇·(ε μ_g ∇u) + ε ρ_g g + f
///
/// ε the gas volume fraction (cell centres; the mean of the two neighbouring cells on a
/// face, of the four around an edge), f the force per unit volume the particles exert on
/// the gas (−Σ drag / V_cell, deposited) plus any source a verification case adds. The
/// viscous stress is taken as ε μ_g ∇u; its transpose part ∇·(ε μ_g (∇u)ᵀ), which vanishes
/// for uniform ε in incompressible flow, is left out (as in several CFD–DEM codes).
///
/// One step of Δt (first order in time, conservative finite volumes, second order in
/// space with central advection):
///  1. predictor  ε_f^{n+1} u* = ε_f^n u^n + Δt/ρ_g [−∇·(ε u u)^n + ∇·(ε μ ∇u)^n
///                               + ε_f^n ρ_g g + f^n] − Δt/ρ_g ε_f^{n+1} ∇p^n
///  2. projection ∇·(ε_f^{n+1} ∇φ) = ρ_g/Δt [∇·(ε_f^{n+1} u*) + (ε^{n+1} − ε^n)/Δt],
///                u^{n+1} = u* − Δt/ρ_g ∇φ,  p^{n+1} = p^n + φ
/// so that ∂ε/∂t + ∇·(ε_f u) = 0 holds discretely at n+1 in every cell. At a steady state
/// φ = 0 and the solution does not depend on Δt. Advection is central (second order) or
/// first-order upwind (robust at high cell Reynolds numbers), chosen per scene. The
/// pressure equation −∇·(d ∇φ) = b, d = ε_f^{n+1} on the faces, is solved by
/// PressureSolver (pressure_solver.hpp): conjugate gradients preconditioned by
/// multigrid (hypre), started from φ = 0 and stopped when ‖b − Aφ‖₂ ≤ tol ‖b‖₂
/// (gas.pressure_tolerance, default 1e-10); or a sparse LDLᵀ factorisation (kept until
/// d changes), by default where the grid's factorisation is the cheaper. The default tolerance keeps the algebraic
/// error ≥ 100× below the discretisation error on the gas MMS case. Continuity then
/// holds to the solver's tolerance rather than to round-off: the residual left in
/// cell c is (Δt/ρ_g)(b − Aφ)_c, at most tol Δt/ρ_g ‖b‖₂.
///
/// Boundaries (staggered_grid.hpp): periodic; no-slip and free-slip walls (normal
/// velocity 0, ∂φ/∂n = 0); velocity inlet (normal velocity given, ∂φ/∂n = 0); pressure
/// outlet (p given on the boundary face, zero normal gradient of velocity; the outlet
/// face velocity is solved for). Without an outlet the pressure is defined up to a
/// constant: its mean is held at zero (added up in exact sums over each process's own
/// planes, so the same bits on any number of processes). A face whose velocity is fixed (wall or inlet) is
/// not solved for; the particles next to it feel the gradient its own steady momentum
/// balance gives (GasField::drag_gradient): the share of the drag reaction a cell hands
/// to such a face stays there, taken by the wall or the inlet, not by the gas.
#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "cdm/solver/fluid/plane_share.hpp"
#include "cdm/solver/fluid/gas_field.hpp"
#include "cdm/solver/fluid/pressure_solver.hpp"
#include "cdm/solver/keywords.hpp"

namespace cdm::fluid {

enum class AdvectionScheme { central, upwind, none };
inline constexpr Keywords<AdvectionScheme, 3> advection_keywords{{{"upwind", AdvectionScheme::upwind}, {"central", AdvectionScheme::central}, {"none", AdvectionScheme::none}}};
inline const char* to_string(AdvectionScheme a) { return keyword_of(advection_keywords, a); }

struct GasSolverSpec {
  AdvectionScheme advection = AdvectionScheme::central;
  Vec3 gravity;  // g acting on the gas [m/s^2] (zero without gravity)
  /// An imposed mean pressure gradient ∇P̄ [Pa/m] on top of the solved (periodic)
  /// pressure: the gas feels −ε∇P̄ (and particles −V_p∇P̄). It lets a box periodic along
  /// gravity carry the weight of what it holds.
  Vec3 mean_pressure_gradient;
  /// The linear solver of the pressure equation and its tolerance.
  PressureSolverSpec pressure;
  /// How the processes of an MPI run share the step (plane_share.hpp).
  GasDivision division = GasDivision::automatic;
};

class GasSolver {
 public:
  GasSolver(GasField& gas, const GasSolverSpec& spec);
  ~GasSolver();

  /// Advance the gas by @p dt from its current state. The caller has put the gas volume
  /// fraction at the end of the step in @p eps_new (padded cell array, ghosts filled)
  /// and the force per unit volume on the gas for the step in force_u/v/w (faces).
  /// eps_new becomes the field's eps_g.
  void step(double dt, const std::vector<double>& eps_new);

  /// Force per unit volume on the gas over the next step, on the faces [N/m^3].
  std::vector<double> force_u, force_v, force_w;
  void clear_force();

  /// The interphase drag treated implicitly over the next step (coupling/implicit_drag.hpp):
  /// β on the faces [kg/(m^3 s)] and β V_s, V_s the particles' mean velocity there
  /// [kg/(m^2 s^2)], or empty (no implicit drag). With them the gas feels β(V_s − u^{n+1})
  /// besides force_*: the predictor solves (ε_f^{n+1} + Δt β/ρ) u* = [explicit part]
  /// + Δt β V_s/ρ − Δt/ρ ε_f^{n+1} ∇p^n, the correction u^{n+1} = u* − Δt/ρ ε_f/(ε_f + Δt β/ρ) ∇φ,
  /// so the pressure operator's coefficient on a face is ε_f²/(ε_f + Δt β/ρ) instead of ε_f.
  std::vector<double> drag_u, drag_v, drag_w;
  std::vector<double> drag_target_u, drag_target_v, drag_target_w;

  /// A manufactured-solution source, added to force_* on every face before each step:
  /// called with the face position, the time at the start of the step and the
  /// component (0 x, 1 y, 2 z). Used by verification cases only.
  std::function<double(Vec3, double, int)> momentum_source;
  /// A mass source per unit volume [1/s] added to the continuity equation at cell
  /// centres (verification only): ∂ε/∂t + ∇·(ε u) = s.
  std::function<double(Vec3, double)> mass_source;

  /// Largest |u| Δt/h and μ Δt/(ρ h²) over the grid for the current velocities. Where
  /// divided() each process scans its planes and the largest is reduced: every process
  /// sharing the step must call max_cfl() and health() alike.
  double max_cfl(double dt) const;
  double diffusion_number(double dt) const;
  /// max_cfl() and whether every stored velocity (the ghosts too) is finite, in one
  /// reduction where divided().
  struct Health {
    double courant = 0.0;
    bool finite = true;
  };
  Health health(double dt) const;
  /// Largest |∇·(ε_f u) + (ε^{n+1} − ε^n)/Δt − s| after the last step [1/s] (the
  /// continuity residual: round-off for the direct solve, bounded by the tolerance for
  /// the multigrid one).
  double continuity_residual() const { return continuity_residual_; }
  /// Pressure-operator setups so far (one per new ε) and the last solve's outcome.
  std::size_t factorisations() const { return pressure_->setups(); }
  const PressureSolveStats& last_pressure_solve() const { return last_solve_; }
  const PressureSolver& pressure_solver() const { return *pressure_; }
  /// Whether the processes of an MPI run divide the step (else each steps the whole gas).
  bool divided() const { return share_.processes() > 1; }
  /// The planes among the processes (each process's own, and those it reads).
  const PlaneShare& planes() const { return share_; }
  /// The planes of cells [@p lo, @p hi] (along z; none where lo > hi) this process reads
  /// the gas on besides those its step reads (its own and two either side): where
  /// divided(), each step then sends it those planes only (PlaneShare::set_reach), and
  /// where any process's reach grew, each receives the gas on its new planes at once.
  /// Collective.
  void read_planes(int lo, int hi);
  /// The planes of cells [first, last) along z a gas field stepped by a GasSolver of
  /// @p division on a grid of @p grid should hold from the start (GasField's planes)
  /// where each process will state the planes it reads (read_planes): where the step is
  /// divided, this process's own planes and those its step reads, else every plane. The
  /// solver takes the field's window for its reach until read_planes() states another.
  static std::pair<int, int> first_planes(GasDivision division, const GridSpec& grid);
  /// The solver's clock (for checkpoints).
  double time() const { return time_; }
  void set_time(double t) {
    time_ = t;
    gas_.set_time(t);
  }
  /// The field was just restored from a checkpoint (GasField::load_state) at time @p t:
  /// its drag gradients, saved whole, stand until the next step (the drag they came from
  /// is not saved: planes received before it keep them).
  void restored(double t) {
    set_time(t);
    gradients_restored_ = true;
  }

 private:
  void predictor(double dt);
  void project(double dt, const std::vector<double>& eps_new);
  /// The field's drag_gradient() on every face whose velocity is fixed, from the drag
  /// of the step just taken (force_*, and β, β V_s with the new velocities) and @p eps.
  void set_drag_gradients(const std::vector<double>& eps);
  /// The velocity, pressure, gas fraction and drag force of every plane in each
  /// process's reach from their owners, and what follows from them.
  void receive_gas();
  /// Every process gets the planes of @p a (staggered as @p s) in its reach, each from
  /// the process that computed it.
  void gather(std::vector<double>& a, Staggering s) const;
  /// The field keeps this process's reach current (GasField::hold_planes); every plane
  /// where the step is not divided.
  void hold_reach();
  bool unknown_face(int axis, int index) const;
  /// unknown_face(axis, i) for every face index i in [0, n(axis)].
  std::vector<char> unknown_faces(int axis) const;

  GasField& gas_;
  GasSolverSpec spec_;
  double time_ = 0.0;
  std::vector<double> us_, vs_, ws_;  // u* (faces)
  std::vector<double> phi_;           // pressure increment (cells, padded)
  std::array<std::vector<double>, 3> d_;  // coefficient of the pressure equation (faces)
  std::vector<double> phi_cells_, b_cells_;  // φ and the right-hand side, one per cell
  std::unique_ptr<PressureSolver> pressure_;
  PlaneShare share_;  // the loops' planes among MPI processes
  bool whole_ = true;  // every process holds every plane of the gas (else its reach's)
  bool gradients_restored_ = false;  // restored(), and no step since
  std::size_t zeroed_at_ = 0;  // the grid's window_moves() when hold_reach() last zeroed beyond it
  PressureSolveStats last_solve_;
  double continuity_residual_ = 0.0;
};

}  // namespace cdm::fluid
