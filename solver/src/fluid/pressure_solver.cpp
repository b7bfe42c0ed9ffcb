#include "cdm/solver/fluid/pressure_solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "pressure_backends.hpp"

namespace cdm::fluid {

PressureSolver::PressureSolver(const StaggeredGrid& grid, const PressureSolverSpec& spec) : grid_(grid), spec_(spec) {
  for (int f = 0; f < 2 * grid_.dims(); ++f)
    has_outlet_ |= grid_.spec().faces[f].kind == BoundaryKind::pressure_outlet;
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
  bool same = true;
  for (int a = 0; a < grid_.dims(); ++a)
    same = same && d_set_[a].size() == d[a]->size() && std::equal(d[a]->begin(), d[a]->end(), d_set_[a].begin());
  if (!same) {
    if (direct_) direct_->set_operator(*this, d);
#ifdef CDM_WITH_MPI
    else multigrid_->set_operator(*this, d);
#endif
    for (int a = 0; a < grid_.dims(); ++a) d_set_[a] = *d[a];
    ++setups_;
  }
  if (!has_outlet_) {
    // Compatibility: without an outlet the sources must balance; remove the round-off.
    double mean = 0.0;
    for (double x : b) mean += x;
    mean /= static_cast<double>(ncell);
    for (double& x : b) x -= mean;
    b[0] = 0.0;  // cell 0 holds φ = 0
  }
#ifdef CDM_WITH_MPI
  if (multigrid_) return multigrid_->solve(b, phi);
#endif
  return direct_->solve(b, phi);
}

// ---------------------------------------------------------------------------------------
// Direct backend.

void PressureSolver::Direct::set_operator(const PressureSolver& ps, const FaceCoefficients& d) {
  const int nx = g_.n(0), ny = g_.n(1), nz = g_.n(2);
  const Eigen::Index ncell = static_cast<Eigen::Index>(nx) * ny * nz;
  auto row = [&](int i, int j, int k) { return static_cast<Eigen::Index>(i + nx * (j + ny * k)); };
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<std::size_t>(ncell) * (2 * g_.dims() + 1));
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const CellStencil s = ps.stencil(d, i, j, k);
        const Eigen::Index r = row(i, j, k);
        for (int a = 0; a < g_.dims(); ++a)
          for (int side = 0; side < 2; ++side) {
            int nb[3] = {i, j, k};
            nb[a] += side == 1 ? 1 : -1;
            const bool boundary = nb[a] < 0 || nb[a] >= g_.n(a);
            if (boundary && !g_.spec().periodic(a)) continue;  // no neighbour: a wall, an inlet or an outlet
            nb[a] = (nb[a] + g_.n(a)) % g_.n(a);
            trip.emplace_back(r, row(nb[0], nb[1], nb[2]), s.off[2 * a + side]);
          }
        trip.emplace_back(r, r, s.diag);
      }
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
