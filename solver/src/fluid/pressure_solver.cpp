#include "cdm/solver/fluid/pressure_solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cdm/solver/exact_sums.hpp"
#include "pressure_backends.hpp"

namespace cdm::fluid {

namespace {

/// For every cell r = (i, j, k) of the operator on @p g (rows x fastest): cell(r, i, j, k),
/// then link(r, c, a, side) for each neighbour c along axis a (side 0 the −a one, 1 the
/// +a one) that is a cell: across an interior face or a periodic wrap, not a wall, an
/// inlet or an outlet.
template <class Cell, class Link>
void for_each_link(const StaggeredGrid& g, Cell&& cell, Link&& link) {
  const int nx = g.n(0), ny = g.n(1), nz = g.n(2);
  auto row = [&](int i, int j, int k) { return static_cast<Eigen::Index>(i + nx * (j + ny * k)); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Eigen::Index r = row(i, j, k);
        cell(r, i, j, k);
        for (int a = 0; a < g.dims(); ++a)
          for (int side = 0; side < 2; ++side) {
            int nb[3] = {i, j, k};
            nb[a] += side == 1 ? 1 : -1;
            const bool boundary = nb[a] < 0 || nb[a] >= g.n(a);
            if (boundary && !g.spec().periodic(a)) continue;
            nb[a] = (nb[a] + g.n(a)) % g.n(a);
            link(r, row(nb[0], nb[1], nb[2]), a, side);
          }
      }
}

/// Eigen's LDLᵀ with the column counts of its symbolic analysis in view.
struct SymbolicLdlt : Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> {
  double sum_of_squared_column_counts() const {
    double w = 0.0;
    for (Eigen::Index j = 0; j < m_nonZerosPerCol.size(); ++j) {
      const double c = m_nonZerosPerCol[j];
      w += c * c;
    }
    return w;
  }
};

}  // namespace

double direct_factor_work_per_cell(const StaggeredGrid& grid) {
  const auto ncell = static_cast<Eigen::Index>(grid.cell_count());
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<std::size_t>(ncell) * (2 * grid.dims() + 1));
  for_each_link(
      grid, [&](Eigen::Index r, int, int, int) { trip.emplace_back(r, r, 2.0 * grid.dims() + 1.0); },
      [&](Eigen::Index r, Eigen::Index c, int, int) { trip.emplace_back(r, c, -1.0); });
  Eigen::SparseMatrix<double> a(ncell, ncell);
  a.setFromTriplets(trip.begin(), trip.end());
  SymbolicLdlt ldlt;
  ldlt.analyzePattern(a);
  return ldlt.sum_of_squared_column_counts() / static_cast<double>(ncell);
}

std::array<int, 3> multigrid_axes(const StaggeredGrid& g) {
  if (g.dims() == 3 && g.n(1) > g.n(0)) return {1, 0, 2};
  return {0, 1, 2};
}

bool direct_is_cheaper(double cells, double lines, double work_per_cell) {
  const double direct = cells * (0.21e-6 + 0.39e-9 * work_per_cell);
  const double multigrid = 220e-6 + 0.35e-6 * cells + 1.6e-6 * lines;
  return direct < multigrid;
}

PressureBackend automatic_backend(const StaggeredGrid& grid) {
  if (!multigrid_available()) return PressureBackend::direct;
  const double cells = static_cast<double>(grid.cell_count());
  // Beyond 1e5 cells the direct solve would need less work per cell than a 2D grid's
  // factorisation does (direct_is_cheaper: below about 360 plus 4100 / line length): not
  // worth the analysis.
  if (cells > 1e5) return PressureBackend::multigrid;
  const double lines = cells / grid.n(multigrid_axes(grid)[0]);
  return direct_is_cheaper(cells, lines, direct_factor_work_per_cell(grid)) ? PressureBackend::direct
                                                                             : PressureBackend::multigrid;
}

PressureSolver::PressureSolver(const StaggeredGrid& grid, const PressureSolverSpec& spec) : grid_(grid), spec_(spec) {
  for (int f = 0; f < 2 * grid_.dims(); ++f)
    has_outlet_ |= grid_.spec().faces[f].kind == BoundaryKind::pressure_outlet;
  if (spec_.backend == PressureBackend::automatic) spec_.backend = automatic_backend(grid_);
  if (spec_.backend == PressureBackend::direct) {
    direct_ = std::make_unique<Direct>(grid_);
    return;
  }
#ifdef CDM_WITH_MPI
  multigrid_ = std::make_unique<Multigrid>(grid_, spec_);
#else
  throw std::invalid_argument("gas pressure solve: the multigrid backend needs MPI and hypre, and this cdm was built "
                              "without them (CDM_WITH_MPI); use the direct backend");
#endif
}

bool multigrid_available() {
#ifdef CDM_WITH_MPI
  return true;
#else
  return false;
#endif
}

PressureSolver::~PressureSolver() = default;

std::string PressureSolver::method() const {
#ifdef CDM_WITH_MPI
  if (multigrid_) return multigrid_->method();
#endif
  return "sparse LDLT (Eigen)";
}

PressureSolver::CellStencil PressureSolver::stencil(const FaceCoefficients& d, int i, int j, int k) const {
  const GridSpec& gs = grid_.spec();
  CellStencil s;
  const int cell[3] = {i, j, k};
  const bool pinned = !has_outlet_;
  if (pinned && i == 0 && j == 0 && k == 0) {
    s.diag = 1.0;  // cell 0 holds φ = 0
    return s;
  }
  for (int a = 0; a < grid_.dims(); ++a) {
    const double w = 1.0 / (grid_.h(a) * grid_.h(a));
    for (int side = 0; side < 2; ++side) {
      int f[3] = {i, j, k};  // the face on this side
      if (side == 1) f[a] += 1;
      int nb[3] = {i, j, k};
      nb[a] = cell[a] + (side == 1 ? 1 : -1);
      const bool boundary = nb[a] < 0 || nb[a] >= grid_.n(a);
      const double ef = (*d[a])[grid_.at(f[0], f[1], f[2])];
      if (!boundary || gs.periodic(a)) {
        s.diag += ef * w;
        nb[a] = (nb[a] + grid_.n(a)) % grid_.n(a);
        // The column of the held cell 0 is zero: its φ = 0 contributes nothing.
        const bool to_held = pinned && nb[0] == 0 && nb[1] == 0 && nb[2] == 0;
        s.off[2 * a + side] = to_held ? 0.0 : -ef * w;
      } else if (gs.faces[2 * a + side].kind == BoundaryKind::pressure_outlet) {
        s.diag += 2.0 * ef * w;
      }
    }
  }
  return s;
}

PressureSolveStats PressureSolver::solve(const FaceCoefficients& d, std::vector<double>& b, std::vector<double>& phi) {
  const std::size_t ncell = grid_.cell_count();
  if (b.size() != ncell || phi.size() != ncell)
    throw std::logic_error("PressureSolver::solve: b and phi need one value per cell");
  // The values of d that solve() reads: the planes coefficient_planes() names (its ghost
  // planes are never set).
  const auto [k0, k1] = coefficient_planes();
  const auto read = [&](const std::vector<double>& v) {
    return std::pair{v.begin() + static_cast<std::ptrdiff_t>(grid_.plane_start(k0)),
                     v.begin() + static_cast<std::ptrdiff_t>(grid_.plane_start(k1))};
  };
  bool same = true;
  for (int a = 0; a < grid_.dims(); ++a) {
    const auto [first, last] = read(*d[a]);
    same = same && d_set_[a].size() == d[a]->size() && std::equal(first, last, d_set_[a].begin() + (first - d[a]->begin()));
  }
#ifdef CDM_WITH_MPI
  if (multigrid_) same = multigrid_->everywhere(same);
#endif
  if (!same) {
    if (direct_) direct_->set_operator(*this, d);
#ifdef CDM_WITH_MPI
    else multigrid_->set_operator(*this, d);
#endif
    for (int a = 0; a < grid_.dims(); ++a) {
      d_set_[a].resize(d[a]->size());
      const auto [first, last] = read(*d[a]);
      std::copy(first, last, d_set_[a].begin() + (first - d[a]->begin()));
    }
    ++setups_;
  }
  if (!has_outlet_) {
    // Compatibility: without an outlet the sources must balance; remove the round-off,
    // their mean: in exact sums (exact_sums.hpp) of the rows this process reads, added up
    // over the processes dividing the solve, so the same bits on any number of them.
    std::size_t r0 = 0, r1 = ncell;
#ifdef CDM_WITH_MPI
    const bool own_rows = reads_own_planes();
    if (own_rows) {
      const auto [k0, k1] = multigrid_->own_planes();
      const std::size_t plane = ncell / static_cast<std::size_t>(grid_.n(2));
      r0 = plane * static_cast<std::size_t>(k0);
      r1 = plane * static_cast<std::size_t>(k1);
    }
#endif
    const auto own = [&](auto&& f) {
      for (std::size_t r = r0; r < r1; ++r) f(b[r]);
    };
    const auto largest = [&](double m) {
#ifdef CDM_WITH_MPI
      if (own_rows) return multigrid_->largest(m);
#endif
      return m;
    };
    const auto add_up = [&]([[maybe_unused]] ExactSums& sum) {
#ifdef CDM_WITH_MPI
      if (own_rows) multigrid_->add_up(sum);
#endif
    };
    // A source not finite is left for the solve to report.
    if (const auto mean = exact_mean(static_cast<double>(ncell), own, largest, add_up))
      for (std::size_t r = r0; r < r1; ++r) b[r] -= *mean;
    b[0] = 0.0;  // cell 0 holds φ = 0
  }
#ifdef CDM_WITH_MPI
  if (multigrid_) return multigrid_->solve(b, phi);
#endif
  return direct_->solve(b, phi);
}

bool PressureSolver::solves_own_planes() const {
#ifdef CDM_WITH_MPI
  return multigrid_ && grid_.dims() == 3 && multigrid_->divided();
#else
  return false;
#endif
}

std::pair<int, int> PressureSolver::coefficient_planes() const {
  const int n = grid_.n(2);
#ifdef CDM_WITH_MPI
  if (multigrid_ && grid_.dims() == 3) {
    const auto [k0, k1] = multigrid_->own_planes();
    return {k0, k0 == k1 ? k0 : k1 + 1};
  }
#endif
  return {0, n + 1};
}

// ---------------------------------------------------------------------------------------
// Direct backend.

void PressureSolver::Direct::set_operator(const PressureSolver& ps, const FaceCoefficients& d) {
  const Eigen::Index ncell = static_cast<Eigen::Index>(g_.cell_count());
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<std::size_t>(ncell) * (2 * g_.dims() + 1));
  CellStencil s;
  for_each_link(
      g_,
      [&](Eigen::Index r, int i, int j, int k) {
        s = ps.stencil(d, i, j, k);
        trip.emplace_back(r, r, s.diag);
      },
      [&](Eigen::Index r, Eigen::Index c, int a, int side) { trip.emplace_back(r, c, s.off[2 * a + side]); });
  A_.resize(ncell, ncell);
  A_.setFromTriplets(trip.begin(), trip.end());
  if (!analysed_) {
    ldlt_.analyzePattern(A_);
    analysed_ = true;
  }
  ldlt_.factorize(A_);
  if (ldlt_.info() != Eigen::Success) throw std::runtime_error("gas pressure equation: factorisation failed");
}

PressureSolveStats PressureSolver::Direct::solve(const std::vector<double>& b, std::vector<double>& phi) const {
  const Eigen::Index ncell = static_cast<Eigen::Index>(b.size());
  const Eigen::Map<const Eigen::VectorXd> bv(b.data(), ncell);
  const Eigen::VectorXd x = ldlt_.solve(bv);
  std::copy(x.data(), x.data() + ncell, phi.begin());
  PressureSolveStats st;
  const double bn = bv.norm();
  if (bn > 0.0) st.relative_residual = (bv - A_ * x).norm() / bn;
  return st;
}

}  // namespace cdm::fluid
