#pragma once
/// @file pressure_solver.hpp
/// @brief The linear solve of the pressure-correction equation on the staggered grid.
///
///   A φ = b,   A φ = −∇·(d ∇φ)  (finite volumes, one unknown per cell)
///
/// d is a coefficient per face (the u, v and w faces), given by the caller at every solve,
/// and b one value per cell. The boundary rules are those of the projection
/// (gas_solver.hpp): a periodic axis wraps; walls and velocity inlets carry no φ flux;
/// a pressure-outlet face holds φ = 0 (ghost value −φ, so the diagonal gains 2 d/h²).
/// Without an outlet, −∇·(d ∇φ) is singular (φ is defined up to a constant) and b must
/// sum to zero: the solver removes the mean of b (the round-off of a balanced source; in
/// exact sums, added up over the processes dividing a multigrid solve) and
/// holds cell 0 at φ = 0 (its row and column become those of the identity, b₀ = 0), for
/// both backends. The system stays symmetric positive definite; the projection does not
/// see the constant (it uses ∇φ, and the pressure's mean is held at zero without an
/// outlet). Pinning rather than a zero-mean solve because PFMG's coarsest level of a
/// singular operator is singular too (a periodic box coarsens to one cell whose operator
/// is 0) and its relaxation there breaks the preconditioner.
///
/// Backends:
///  - multigrid (in a build with MPI and hypre): conjugate gradients
///    preconditioned by one V-cycle of hypre's structured-grid multigrid PFMG
///    (semi-coarsening, PFMG's non-Galerkin coarse operators, smoothing skipped where
///    redundant: symmetric red–black Gauss–Seidel without periodic axes, weighted
///    Jacobi with them), on hypre's Struct interface over MPI_COMM_WORLD: under
///    mpirun the processes divide the solve (each owns whole planes of cells) and every
///    process gets the whole φ, the same to the bit as one process's, so every process
///    must construct and call it alike (pressure_multigrid.cpp); or, where the spec says
///    it is not divided, each solves the whole alone.
///    Converged when ‖b − Aφ‖₂ ≤ tolerance ‖b‖₂. Work and memory O(N) in the cells.
///  - direct: Eigen's sparse LDLᵀ factorisation, O(N^{5/3}) or worse in 3D, kept until d
///    changes; exact to round-off. The reference the multigrid solver is tested against,
///    and the only backend of a build without MPI and hypre.
///  - automatic (the default): direct where the grid's factorisation is cheap enough that
///    a factorisation and solve cost less than a multigrid solve (small grids, and grids
///    thin along two axes), multigrid otherwise (automatic_backend).
#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cdm/solver/fluid/staggered_grid.hpp"
#include "cdm/solver/keywords.hpp"

namespace cdm::fluid {

enum class PressureBackend { automatic, multigrid, direct };
inline constexpr Keywords<PressureBackend, 3> pressure_backend_keywords{{{"auto", PressureBackend::automatic},
                                                                         {"multigrid", PressureBackend::multigrid},
                                                                         {"direct", PressureBackend::direct}}};
inline const char* to_string(PressureBackend b) { return keyword_of(pressure_backend_keywords, b); }

struct PressureSolverSpec {
  PressureBackend backend = PressureBackend::automatic;
  /// Relative residual ‖b − Aφ‖₂/‖b‖₂ at which the multigrid backend stops. The default
  /// keeps the algebraic error ≥ 100× below the discretisation error of the gas MMS case
  /// (verification/cases/gas_mms/README.md).
  double tolerance = 1e-10;
  static constexpr double min_tolerance = 1e-14, max_tolerance = 1e-3;
  /// Under mpirun: whether the processes divide the multigrid solve among them (true),
  /// or each solves the whole alone (the gas step's division, plane_share.hpp).
  bool divided = true;
};

/// Outcome of one solve.
struct PressureSolveStats {
  int iterations = 0;              // Krylov iterations (0 for the direct backend)
  double relative_residual = 0.0;  // ‖b − Aφ‖₂/‖b‖₂ (0 when b = 0)
};

/// Whether this build has the multigrid backend: it needs MPI and hypre (CMake option
/// CDM_WITH_MPI, on when both are found). Without it only the direct backend exists.
bool multigrid_available();

/// The work of one LDLᵀ factorisation of the pressure operator on @p grid, per cell:
/// Σ_j c_j² / cells, c_j the entries below the diagonal in column j of the factor L
/// (Eigen's fill-reducing ordering). About the factorisation's multiply–adds per cell.
double direct_factor_work_per_cell(const StaggeredGrid& grid);

/// Whether one factorisation and solve is estimated to cost less than one multigrid
/// setup and solve on a grid of @p cells cells in @p lines lines along the multigrid's
/// first axis (cells / n_y where y is longer than x in 3D, else cells / n_x),
/// whose factorisation does @p work_per_cell (direct_factor_work_per_cell). The
/// estimates, fitted to bench/gas_poisson on 28 grids of 27 to 32,768 cells (cubes, slabs
/// and columns, each axis the short one; bench/README.md): direct 0.21 µs per cell plus
/// 0.39 ns per unit of factorisation work; multigrid 220 µs (hypre's fixed cost) plus
/// 0.35 µs per cell plus 1.6 µs per line (hypre's loops run along its first axis: lines
/// of 2 cells cost twice what lines of 90 do).
bool direct_is_cheaper(double cells, double lines, double work_per_cell);

/// The backend PressureBackend::automatic resolves to on @p grid: direct where
/// direct_is_cheaper or the build has no multigrid backend, multigrid otherwise.
PressureBackend automatic_backend(const StaggeredGrid& grid);

class PressureSolver {
 public:
  /// Built once for a grid and its boundary kinds. The multigrid backend initialises MPI
  /// on first use if the program has not (mpi_session.hpp); in a build without it
  /// (multigrid_available() false) asking for it throws std::invalid_argument.
  PressureSolver(const StaggeredGrid& grid, const PressureSolverSpec& spec);
  ~PressureSolver();
  PressureSolver(const PressureSolver&) = delete;
  PressureSolver& operator=(const PressureSolver&) = delete;

  /// Solve A φ = b. @p d holds the face coefficients of the u, v and w faces in padded
  /// arrays (StaggeredGrid::make_array; faces 0..n along each axis, the w faces unused in
  /// 2D). @p b and @p phi have one value per cell, x fastest: b is modified (its mean is
  /// removed without an outlet); phi is the start (multigrid) and receives the solution.
  PressureSolveStats solve(const std::array<const std::vector<double>*, 3>& d, std::vector<double>& b,
                           std::vector<double>& phi);

  /// Operator setups so far (a factorisation or a multigrid hierarchy; one per new d).
  std::size_t setups() const { return setups_; }
  /// The method in use, e.g. "PCG + PFMG (hypre)".
  std::string method() const;
  /// The backend in use (never automatic: what it resolved to).
  PressureBackend backend() const { return spec_.backend; }
  /// Whether solve() reads of b only the cells of this process's planes (its run of
  /// PlaneShare::planes_of the z axis), so that the other processes' parts need not be
  /// sent to it: a 3D grid's multigrid solve (without an outlet, b's mean is added up
  /// over the processes). A direct solve reads every cell.
  bool reads_own_planes() const { return multigrid_ && grid_.dims() == 3; }
  /// Whether solve() sets of φ only the cells of this process's planes, the caller
  /// gathering the rest (PlaneShare::gather): a 3D grid's multigrid solve divided among
  /// processes. Else it sets every cell.
  bool solves_own_planes() const;
  /// The planes [first, last) of the z axis whose face coefficients (d, all three
  /// components) solve() reads: this process's planes of cells and the plane of faces
  /// above them, where a 3D grid's multigrid solve is divided among the processes, else
  /// every plane. The other planes of d need not be set; the processes then decide
  /// together whether d changed.
  std::pair<int, int> coefficient_planes() const;

  /// The operator's coefficients for one cell: diagonal and the off-diagonal entry to
  /// each neighbour, sides ordered (−x, +x, −y, +y, −z, +z); an entry is 0 where the face
  /// carries no φ flux or the neighbour is the held cell 0. Both backends assemble from it.
  struct CellStencil {
    double diag = 0.0;
    std::array<double, 6> off{};
  };
  CellStencil stencil(const std::array<const std::vector<double>*, 3>& d, int i, int j, int k) const;

 private:
  class Direct;
  class Multigrid;
  StaggeredGrid grid_;
  PressureSolverSpec spec_;
  bool has_outlet_ = false;
  std::unique_ptr<Direct> direct_;
  std::unique_ptr<Multigrid> multigrid_;
  std::array<std::vector<double>, 3> d_set_;  // d of the current setup
  std::size_t setups_ = 0;
};

}  // namespace cdm::fluid
