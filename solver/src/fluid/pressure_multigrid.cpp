/// @file pressure_multigrid.cpp
/// @brief The multigrid backend of PressureSolver: hypre's Struct PCG preconditioned by
/// one V(1,1)-cycle of PFMG, shared among the processes of an MPI run.
///
/// PFMG with Jacobi smoothing converges in 10–15 iterations (tolerance 1e-10) on every
/// grid of tests/coupling/test_pressure_solver.cpp: periodic axes of 2, 3, 4, 5, 6, 9, 10,
/// 12, 16, 18, 24 and 128 cells, odd or even, 2D and 3D, walls, inlets and outlets.
/// hypre's SMG, the other Struct multigrid, is no fallback: on the periodic grids it did
/// not converge (relative residual 0.7 after one iteration, or 4e-4 after 1000).
///
/// Shared among ranks: under mpirun every process holds the whole gas and steps it alike
/// (rank_split.hpp), dividing the step's loops and this solve where that pays
/// (PressureSolverSpec::divided, plane_share.hpp). Each rank
/// owns a run of whole planes of the slowest axis (z in 3D, y in 2D; owned_box), gives
/// hypre its part of the operator and of b, and the parts of φ are gathered back to every
/// rank after the solve. Every process must therefore construct the solver and call
/// set_operator and solve alike. φ is the same to the bit on any number of ranks:
///  - hypre's smoothing, restriction, interpolation and products with A are pointwise,
///    the same arithmetic whichever rank holds a cell;
///  - PCG's inner products are the one reduction: they are summed plane by plane, each
///    plane by its owner in the cells' order, and the planes' sums are added in plane
///    order on every rank (PlaneSums), instead of hypre's own sum over each rank's cells;
///  - PFMG's coarsening follows its estimate of the operator's strength along each axis
///    (its "dxyz"), which hypre reduces over the ranks in rank order: it is computed here
///    with the same plane-ordered sums and handed to PFMG.
#include <HYPRE_struct_ls.h>
#include <_hypre_struct_ls.h>
#include <_hypre_struct_mv.h>
#include <krylov.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "cdm/solver/fluid/plane_share.hpp"
#include "cdm/solver/mpi_session.hpp"
#include "pressure_backends.hpp"

namespace cdm::fluid {

namespace {

/// The planes of the slowest axis a rank owns: those the gas step's loops give it.
std::pair<int, int> owned_planes(int planes, int rank, int size) { return PlaneShare::planes_of(planes, rank, size); }

/// The cells [lo, hi] (inclusive, hypre's convention) a rank owns; empty = false.
struct Box {
  bool empty = true;
  HYPRE_Int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
};

Box owned_box(const StaggeredGrid& g, const std::array<int, 3>& axes, int rank, int size) {
  const int slow = g.dims() - 1;
  const auto [first, last] = owned_planes(g.n(slow), rank, size);
  Box b;
  if (first == last) return b;
  b.empty = false;
  for (int a = 0; a < 3; ++a) b.hi[a] = g.n(axes[static_cast<std::size_t>(a)]) - 1;
  b.lo[slow] = first;
  b.hi[slow] = last - 1;
  return b;
}

/// Sums over the cells that come out the same to the bit on any number of ranks: each
/// rank adds its cells plane by plane (m sums per plane, the other planes' left 0), the
/// planes' sums are shared (an exact sum: each plane's comes from its one owner, the
/// other ranks add zeros) and every rank adds them up in plane order.
class PlaneSums {
 public:
  /// @p planes planes of axis @p slow (1 or 2), the first at index @p first; m sums each.
  PlaneSums(int slow, int first, int planes, int m)
      : slow_(slow), first_(first), m_(m), sums_(static_cast<std::size_t>(planes) * static_cast<std::size_t>(m), 0.0) {}
  /// The m sums of the plane holding the row of cells (j, k).
  double* row(int j, int k) {
    const int p = (slow_ == 2 ? k : j) - first_;
    return &sums_[static_cast<std::size_t>(p) * static_cast<std::size_t>(m_)];
  }
  /// The m totals, into @p total.
  void total(MPI_Comm comm, double* total) {
    int size = 1;
    MPI_Comm_size(comm, &size);
    if (size > 1)
      MPI_Allreduce(MPI_IN_PLACE, sums_.data(), static_cast<int>(sums_.size()), MPI_DOUBLE, MPI_SUM, comm);
    for (int c = 0; c < m_; ++c) total[c] = 0.0;
    for (std::size_t q = 0; q < sums_.size(); q += static_cast<std::size_t>(m_))
      for (int c = 0; c < m_; ++c) total[c] += sums_[q + static_cast<std::size_t>(c)];
  }

 private:
  int slow_, first_, m_;
  std::vector<double> sums_;
};

/// PCG's inner product <x, y>, summed with PlaneSums (hypre's Krylov interface: x and y
/// are hypre_StructVector on the same grid; the slowest axis is the grid's last).
HYPRE_Real plane_ordered_inner_product(void* vx, void* vy) {
  auto* x = static_cast<hypre_StructVector*>(vx);
  auto* y = static_cast<hypre_StructVector*>(vy);
  hypre_StructGrid* grid = hypre_StructVectorGrid(x);
  const int ndim = hypre_StructGridNDim(grid);
  const int slow = ndim - 1;
  hypre_Box* whole = hypre_StructGridBoundingBox(grid);
  const HYPRE_Int p0 = hypre_BoxIMinD(whole, slow);
  PlaneSums sums(slow, static_cast<int>(p0), static_cast<int>(hypre_BoxIMaxD(whole, slow) - p0 + 1), 1);
  hypre_BoxArray* boxes = hypre_StructGridBoxes(grid);
  for (HYPRE_Int bi = 0; bi < hypre_BoxArraySize(boxes); ++bi) {
    hypre_Box* box = hypre_BoxArrayBox(boxes, bi);
    const double* xs = hypre_StructVectorBoxData(x, bi);
    const double* ys = hypre_StructVectorBoxData(y, bi);
    hypre_Box* xd = hypre_BoxArrayBox(hypre_StructVectorDataSpace(x), bi);
    hypre_Box* yd = hypre_BoxArrayBox(hypre_StructVectorDataSpace(y), bi);
    HYPRE_Int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, xo[3] = {0, 0, 0}, yo[3] = {0, 0, 0};
    long xs1 = 0, xs2 = 0, ys1 = 0, ys2 = 0;
    for (int a = 0; a < ndim; ++a) {
      lo[a] = hypre_BoxIMinD(box, a);
      hi[a] = hypre_BoxIMaxD(box, a);
      xo[a] = hypre_BoxIMinD(xd, a);
      yo[a] = hypre_BoxIMinD(yd, a);
    }
    xs1 = hypre_BoxSizeD(xd, 0);
    ys1 = hypre_BoxSizeD(yd, 0);
    xs2 = ndim > 2 ? xs1 * hypre_BoxSizeD(xd, 1) : 0;
    ys2 = ndim > 2 ? ys1 * hypre_BoxSizeD(yd, 1) : 0;
    for (HYPRE_Int k = lo[2]; k <= hi[2]; ++k)
      for (HYPRE_Int j = lo[1]; j <= hi[1]; ++j) {
        const double* xr = xs + (lo[0] - xo[0]) + xs1 * (j - xo[1]) + xs2 * (k - xo[2]);
        const double* yr = ys + (lo[0] - yo[0]) + ys1 * (j - yo[1]) + ys2 * (k - yo[2]);
        double* s = sums.row(static_cast<int>(j), static_cast<int>(k));
        for (HYPRE_Int i = 0; i <= hi[0] - lo[0]; ++i) *s += xr[i] * yr[i];
      }
  }
  double total = 0.0;
  sums.total(hypre_StructVectorComm(x), &total);
  return total;
}

void check(HYPRE_Int rc, const char* what) {
  if (rc != 0 && !(rc & HYPRE_ERROR_CONV)) {
    HYPRE_ClearAllErrors();
    throw std::runtime_error(std::string("gas pressure equation: hypre ") + what + " failed (error " +
                             std::to_string(rc) + ")");
  }
}

}  // namespace

struct PressureSolver::Multigrid::Hypre {
  MPI_Comm comm = MPI_COMM_SELF;
  int ndim = 3, rank = 0, size = 1;
  std::array<int, 3> axes{0, 1, 2};  // multigrid_axes
  Box box;
  std::vector<int> counts, offsets;  // per rank: its cells in the cell array (x fastest)
  HYPRE_StructGrid grid = nullptr;
  HYPRE_StructStencil stencil = nullptr;
  HYPRE_StructMatrix A = nullptr;
  HYPRE_StructVector b = nullptr, x = nullptr;
  HYPRE_StructSolver pcg = nullptr, pre = nullptr;
  std::vector<double> values;  // scratch for SetBoxValues
  std::vector<double> swapped;  // this rank's b or φ in hypre's order, where x and y swap
  /// This rank's cells of @p grid_order (x fastest) into swapped, in hypre's order.
  void to_hypre(const StaggeredGrid& g, const double* grid_order) {
    swapped.resize(static_cast<std::size_t>(counts[static_cast<std::size_t>(rank)]));
    for_swapped(g, [&](std::size_t hq, std::size_t gq) { swapped[hq] = grid_order[gq]; });
  }
  /// swapped back into this rank's cells of @p grid_order.
  void from_hypre(const StaggeredGrid& g, double* grid_order) const {
    for_swapped(g, [&](std::size_t hq, std::size_t gq) { grid_order[gq] = swapped[hq]; });
  }
  /// f(hypre's index, the grid's index) for each of this rank's cells (x and y swapped).
  template <class F>
  void for_swapped(const StaggeredGrid& g, F&& f) const {
    const std::size_t nx = static_cast<std::size_t>(g.n(0)), ny = static_cast<std::size_t>(g.n(1));
    const std::size_t n = static_cast<std::size_t>(counts[static_cast<std::size_t>(rank)]);
    for (std::size_t q = 0; q < n; q += nx * ny)  // one plane of z at a time
      for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) f(q + j + ny * i, q + i + nx * j);
  }
};

PressureSolver::Multigrid::Multigrid(const StaggeredGrid& g, const PressureSolverSpec& spec)
    : g_(g), tolerance_(spec.tolerance), h_(std::make_unique<Hypre>()) {
  ensure_mpi();
  Hypre& h = *h_;
  int world = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &world);
  if (world > 1 && spec.divided) h.comm = MPI_COMM_WORLD;
  MPI_Comm_rank(h.comm, &h.rank);
  MPI_Comm_size(h.comm, &h.size);
  h.ndim = g.dims();
  h.axes = multigrid_axes(g);
  h.box = owned_box(g, h.axes, h.rank, h.size);
  const int slow = h.ndim - 1;
  const std::size_t per_plane = g.cell_count() / static_cast<std::size_t>(g.n(slow));
  for (int r = 0; r < h.size; ++r) {
    const auto [first, last] = owned_planes(g.n(slow), r, h.size);
    h.offsets.push_back(static_cast<int>(per_plane * static_cast<std::size_t>(first)));
    h.counts.push_back(static_cast<int>(per_plane * static_cast<std::size_t>(last - first)));
  }
  check(HYPRE_StructGridCreate(h.comm, h.ndim, &h.grid), "grid");
  if (!h.box.empty) HYPRE_StructGridSetExtents(h.grid, h.box.lo, h.box.hi);
  HYPRE_Int period[3] = {0, 0, 0};
  for (int a = 0; a < h.ndim; ++a) {
    const int ga = h.axes[static_cast<std::size_t>(a)];
    if (g.spec().periodic(ga)) period[a] = g.n(ga);
  }
  HYPRE_StructGridSetPeriodic(h.grid, period);
  check(HYPRE_StructGridAssemble(h.grid), "grid assembly");
  // Stencil entries: 0 the cell, then −x, +x, −y, +y (, −z, +z) along hypre's axes.
  const int entries = 1 + 2 * h.ndim;
  HYPRE_StructStencilCreate(h.ndim, entries, &h.stencil);
  HYPRE_Int centre[3] = {0, 0, 0};
  HYPRE_StructStencilSetElement(h.stencil, 0, centre);
  for (int a = 0; a < h.ndim; ++a)
    for (int side = 0; side < 2; ++side) {
      HYPRE_Int off[3] = {0, 0, 0};
      off[a] = side == 1 ? 1 : -1;
      HYPRE_StructStencilSetElement(h.stencil, 1 + 2 * a + side, off);
    }
  for (HYPRE_StructVector* v : {&h.b, &h.x}) {
    check(HYPRE_StructVectorCreate(h.comm, h.grid, v), "vector");
    HYPRE_StructVectorInitialize(*v);
    HYPRE_StructVectorAssemble(*v);
  }
}

void PressureSolver::Multigrid::destroy_solver() {
  Hypre& h = *h_;
  if (h.pcg) HYPRE_StructPCGDestroy(h.pcg);
  if (h.pre) HYPRE_StructPFMGDestroy(h.pre);
  if (h.A) HYPRE_StructMatrixDestroy(h.A);
  h.pcg = h.pre = nullptr;
  h.A = nullptr;
}

PressureSolver::Multigrid::~Multigrid() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;  // MPI is gone (exit): hypre's objects go with the process
  destroy_solver();
  Hypre& h = *h_;
  HYPRE_StructVectorDestroy(h.b);
  HYPRE_StructVectorDestroy(h.x);
  HYPRE_StructStencilDestroy(h.stencil);
  HYPRE_StructGridDestroy(h.grid);
}

std::string PressureSolver::Multigrid::method() const { return "PCG + PFMG (hypre)"; }

std::pair<int, int> PressureSolver::Multigrid::own_planes() const {
  return owned_planes(g_.n(g_.dims() - 1), h_->rank, h_->size);
}

bool PressureSolver::Multigrid::divided() const { return h_->size > 1; }

bool PressureSolver::Multigrid::everywhere(bool here) const {
  if (h_->size <= 1) return here;
  int all = here ? 1 : 0;
  if (MPI_Allreduce(MPI_IN_PLACE, &all, 1, MPI_INT, MPI_LAND, h_->comm) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allreduce of whether the pressure operator changed failed");
  return all != 0;
}

double PressureSolver::Multigrid::largest(double x) const {
  if (h_->size > 1 && MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE, MPI_MAX, h_->comm) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allreduce of the right-hand side's largest value failed");
  return x;
}

void PressureSolver::Multigrid::add_up(ExactSums& s) const {
  if (h_->size > 1 && MPI_Allreduce(MPI_IN_PLACE, s.data(), static_cast<int>(s.size()), MPI_INT64_T, MPI_SUM,
                                    h_->comm) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allreduce of the right-hand side's sum failed");
}

void PressureSolver::Multigrid::set_operator(const PressureSolver& ps, const FaceCoefficients& d) {
  destroy_solver();
  Hypre& h = *h_;
  // Symmetric storage: the cell and its lower neighbours (−x, −y, −z); hypre takes each
  // upper entry from the neighbour's lower one. A is symmetric (a face's coefficient is
  // the same seen from either cell, the held cell's row and column are both cleared).
  const int stored = 1 + h.ndim;
  check(HYPRE_StructMatrixCreate(h.comm, h.grid, h.stencil, &h.A), "matrix");
  HYPRE_StructMatrixSetSymmetric(h.A, 1);
  HYPRE_StructMatrixInitialize(h.A);
  // PFMG's strength of the operator along each axis, as hypre_PFMGComputeDxyz sums it
  // (per cell c_a = −sign(diag) (off⁻ + off⁺) along axis a, and c_a²), in plane order.
  const int slow = h.ndim - 1;
  PlaneSums strength(slow, 0, g_.n(slow), 6);
  if (!h.box.empty) {
    h.values.resize(static_cast<std::size_t>(h.counts[static_cast<std::size_t>(h.rank)]) *
                    static_cast<std::size_t>(stored));
    std::size_t q = 0;
    const auto& ax = h.axes;
    for (int k = h.box.lo[2]; k <= h.box.hi[2]; ++k)
      for (int j = h.box.lo[1]; j <= h.box.hi[1]; ++j) {
        double* c = strength.row(j, k);
        for (int i = h.box.lo[0]; i <= h.box.hi[0]; ++i) {
          int cell[3];  // the grid's indices of hypre's cell (i, j, k)
          cell[ax[0]] = i; cell[ax[1]] = j; cell[ax[2]] = k;
          const CellStencil s = ps.stencil(d, cell[0], cell[1], cell[2]);
          h.values[q++] = s.diag;
          for (int a = 0; a < h.ndim; ++a) h.values[q++] = s.off[static_cast<std::size_t>(2 * ax[static_cast<std::size_t>(a)])];
          const double sign = s.diag < 0.0 ? -1.0 : 1.0;
          for (int a = 0; a < h.ndim; ++a) {
            const std::size_t ga = static_cast<std::size_t>(ax[static_cast<std::size_t>(a)]);
            const double ca = -sign * (s.off[2 * ga] + s.off[2 * ga + 1]);
            c[a] += ca;
            c[3 + a] += ca * ca;
          }
        }
      }
    HYPRE_Int ent[4] = {0, 1, 3, 5};
    check(HYPRE_StructMatrixSetBoxValues(h.A, h.box.lo, h.box.hi, stored, ent, h.values.data()), "matrix values");
  }
  check(HYPRE_StructMatrixAssemble(h.A), "matrix assembly");

  double c[6];
  strength.total(h.comm, c);
  // hypre_PFMGComputeDxyz's arithmetic on those sums: the axes' spacings as PFMG sees
  // them, and whether the coefficients vary enough (squared coefficient of variation
  // above 0.1) for PFMG to weight its Jacobi sweeps 2/3 on every level.
  double dxyz[3] = {0.0, 0.0, 0.0};
  bool varied = false;
  const double cells = static_cast<double>(g_.cell_count());
  for (int a = 0; a < h.ndim; ++a) {
    const double mean = c[a] / cells;
    if (c[3 + a] / cells - mean * mean > 0.1 * mean * mean) varied = true;
  }
  double c_max = std::max({c[0], c[1], c[2]});
  if (c_max == 0.0) {
    c[0] = c[1] = c[2] = 1.0;
    c_max = 1.0;
  }
  const double max_anisotropy = HYPRE_REAL_MAX / 1000.0;
  for (int a = 0; a < 3; ++a)
    dxyz[a] = c[a] > c_max / max_anisotropy ? std::sqrt(1.0 / (c[a] / c_max)) : std::sqrt(max_anisotropy);

  // HYPRE_StructPCGCreate's PCG with the inner product summed in plane order.
  hypre_PCGFunctions* pcg = hypre_PCGFunctionsCreate(
      hypre_StructKrylovCAlloc, hypre_StructKrylovFree, hypre_StructKrylovCommInfo, hypre_StructKrylovCreateVector,
      hypre_StructKrylovDestroyVector, hypre_StructKrylovMatvecCreate, hypre_StructKrylovMatvec,
      hypre_StructKrylovMatvecDestroy, plane_ordered_inner_product, hypre_StructKrylovCopyVector,
      hypre_StructKrylovClearVector, hypre_StructKrylovScaleVector, hypre_StructKrylovAxpy,
      hypre_StructKrylovIdentitySetup, hypre_StructKrylovIdentity);
  h.pcg = static_cast<HYPRE_StructSolver>(hypre_PCGCreate(pcg));
  HYPRE_StructPCGSetTol(h.pcg, tolerance_);
  HYPRE_StructPCGSetAbsoluteTol(h.pcg, 0.0);
  HYPRE_StructPCGSetTwoNorm(h.pcg, 1);
  HYPRE_StructPCGSetRelChange(h.pcg, 0);
  HYPRE_StructPCGSetMaxIter(h.pcg, 1000);
  HYPRE_StructPFMGCreate(h.comm, &h.pre);
  HYPRE_StructPFMGSetMaxIter(h.pre, 1);
  HYPRE_StructPFMGSetTol(h.pre, 0.0);
  HYPRE_StructPFMGSetZeroGuess(h.pre);
  // Smoothing: PFMG's symmetric red–black Gauss–Seidel on a grid without periodic axes
  // (fewer iterations, each hardly dearer: bench/README.md), weighted Jacobi otherwise.
  // Red–black Gauss–Seidel is not symmetric, as conjugate gradients need, on a periodic
  // axis of odd length (no two-colouring) or where the coarsening reaches two periodic
  // cells: there it stalled (4×8×4 periodic in x and z: relative residual 2e-9 after
  // 1000 iterations) where Jacobi takes 12.
  // Relaxation is skipped on the levels where PFMG finds it redundant for an isotropic
  // operator (hypre's "skip relax"), and the coarse operators are PFMG's non-Galerkin ones
  // (RAP type 1) rather than R·A·P: a few more iterations, each much cheaper
  // (bench/README.md, the pressure solve). Both only change the preconditioner: the
  // stopping test on the residual is the same.
  bool periodic = false;
  for (int a = 0; a < h.ndim; ++a) periodic = periodic || g_.spec().periodic(a);
  HYPRE_StructPFMGSetRelaxType(h.pre, periodic ? 1 : 2);
  HYPRE_StructPFMGSetSkipRelax(h.pre, 1);
  HYPRE_StructPFMGSetRAPType(h.pre, 1);
  HYPRE_StructPFMGSetNumPreRelax(h.pre, 1);
  HYPRE_StructPFMGSetNumPostRelax(h.pre, 1);
  HYPRE_StructPFMGSetDxyz(h.pre, dxyz);
  if (varied) HYPRE_StructPFMGSetJacobiWeight(h.pre, 2.0 / 3.0);
  HYPRE_StructPCGSetPrecond(h.pcg, HYPRE_StructPFMGSolve, HYPRE_StructPFMGSetup, h.pre);
  check(HYPRE_StructPCGSetup(h.pcg, h.A, h.b, h.x), "multigrid setup");
}

PressureSolveStats PressureSolver::Multigrid::solve(const std::vector<double>& b, std::vector<double>& phi) {
  Hypre& h = *h_;
  const std::size_t mine = static_cast<std::size_t>(h.offsets[static_cast<std::size_t>(h.rank)]);
  const bool swap = h.axes[0] != 0;
  // This rank's cells of @p v as hypre reads them: in place, or reordered into swapped.
  auto in_hypre_order = [&](const double* v) {
    if (!swap) return const_cast<double*>(v);  // hypre's setters take a non-const pointer
    h.to_hypre(g_, v);
    return h.swapped.data();
  };
  if (!h.box.empty) {
    HYPRE_StructVectorSetBoxValues(h.b, h.box.lo, h.box.hi, in_hypre_order(b.data() + mine));
    HYPRE_StructVectorSetBoxValues(h.x, h.box.lo, h.box.hi, in_hypre_order(phi.data() + mine));
  }
  HYPRE_StructVectorAssemble(h.b);
  HYPRE_StructVectorAssemble(h.x);
  check(HYPRE_StructPCGSolve(h.pcg, h.A, h.b, h.x), "PCG solve");
  PressureSolveStats st;
  HYPRE_Int it = 0;
  HYPRE_StructPCGGetNumIterations(h.pcg, &it);
  HYPRE_StructPCGGetFinalRelativeResidualNorm(h.pcg, &st.relative_residual);
  st.iterations = static_cast<int>(it);
  HYPRE_ClearAllErrors();
  if (!h.box.empty) {
    HYPRE_StructVectorGetBoxValues(h.x, h.box.lo, h.box.hi, swap ? h.swapped.data() : phi.data() + mine);
    if (swap) h.from_hypre(g_, phi.data() + mine);
  }
  // A 3D grid's caller gathers φ's planes (PressureSolver::solves_own_planes).
  if (h.size > 1 && g_.dims() != 3)
    MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, phi.data(), h.counts.data(), h.offsets.data(), MPI_DOUBLE,
                   h.comm);
  if (!(st.relative_residual <= tolerance_)) {
    std::ostringstream os;
    os << "gas pressure equation: " << method() << " did not converge: relative residual " << st.relative_residual
       << " after " << st.iterations << " iterations (tolerance " << tolerance_ << ")";
    throw std::runtime_error(os.str());
  }
  return st;
}

}  // namespace cdm::fluid
