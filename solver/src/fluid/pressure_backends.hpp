#pragma once
/// @file pressure_backends.hpp
/// @brief The two backends of PressureSolver (pressure_solver.hpp): direct (Eigen LDLᵀ,
/// pressure_solver.cpp) and multigrid (hypre Struct PCG + PFMG, pressure_multigrid.cpp).
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/fluid/pressure_solver.hpp"

namespace cdm::fluid {

using FaceCoefficients = std::array<const std::vector<double>*, 3>;

/// The grid's axis along each of the multigrid backend's (hypre's): hypre's loops run
/// along its first axis and cost per cell about twice as much on lines of 2 cells as on
/// lines of 30 or more (bench/README.md), so in 3D the longer of x and y goes first; the
/// slowest axis, whose planes the ranks own, stays last. Its own inverse.
std::array<int, 3> multigrid_axes(const StaggeredGrid& g);

/// Eigen's sparse LDLᵀ of A.
class PressureSolver::Direct {
 public:
  explicit Direct(const StaggeredGrid& g) : g_(g) {}
  void set_operator(const PressureSolver& ps, const FaceCoefficients& d);
  PressureSolveStats solve(const std::vector<double>& b, std::vector<double>& phi) const;

 private:
  const StaggeredGrid& g_;
  Eigen::SparseMatrix<double> A_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  bool analysed_ = false;
};

#ifdef CDM_WITH_MPI
/// hypre's Struct PCG preconditioned by PFMG (or SMG where PFMG cannot coarsen soundly).
class PressureSolver::Multigrid {
 public:
  Multigrid(const StaggeredGrid& g, const PressureSolverSpec& spec);
  ~Multigrid();
  Multigrid(const Multigrid&) = delete;
  Multigrid& operator=(const Multigrid&) = delete;
  void set_operator(const PressureSolver& ps, const FaceCoefficients& d);
  PressureSolveStats solve(const std::vector<double>& b, std::vector<double>& phi);
  std::string method() const;
  /// This process's planes [first, last) of cells along the slowest axis (z in 3D).
  std::pair<int, int> own_planes() const;
  /// Whether @p here holds on every process dividing the solve.
  bool everywhere(bool here) const;
  /// The largest of @p x over the processes.
  double largest(double x) const;
  /// @p s's sums added up over the processes.
  void add_up(ExactSums& s) const;
  /// Whether more than one process divides the solve.
  bool divided() const;

 private:
  struct Hypre;  // the hypre objects (keeps hypre's headers out of this one)
  void destroy_solver();
  const StaggeredGrid& g_;
  double tolerance_;
  std::unique_ptr<Hypre> h_;
};
#else
/// A build without MPI and hypre has no multigrid backend (multigrid_available() is
/// false, so PressureSolver never makes one): the type only completes the member that
/// would hold it.
class PressureSolver::Multigrid {};
#endif

}  // namespace cdm::fluid
