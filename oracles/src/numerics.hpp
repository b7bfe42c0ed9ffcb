#pragma once
// Private helpers shared by the gas oracles: a CVODE integrator that owns its SUNDIALS
// objects (BDF, dense Newton, SUNContext), and GSL Brent root finding. Not installed:
// only oracles/src/*.cpp include this.
#include <functional>
#include <vector>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

namespace cdm::oracles::detail {

/// y' = f(t, y) for a small dense system; f writes dy from y.
using OdeRhs = std::function<void(double t, const double* y, double* dy)>;

class Cvode {
 public:
  /// rtol relative tolerance; atol one absolute tolerance per component.
  Cvode(OdeRhs rhs, const std::vector<double>& y0, double t0, double rtol, const std::vector<double>& atol,
        const char* who);
  ~Cvode();
  Cvode(const Cvode&) = delete;
  Cvode& operator=(const Cvode&) = delete;

  /// Integrate to t (>= the last requested time) and return the state there.
  const std::vector<double>& advance(double t);
  /// Restart from a new initial state (same tolerances).
  void reinit(const std::vector<double>& y0, double t0);
  long steps() const;

 private:
  static int rhs_thunk(sunrealtype t, N_Vector y, N_Vector dy, void* self);
  void check(int flag, const char* what) const;

  OdeRhs rhs_;
  const char* who_;
  int n_;
  SUNContext ctx_ = nullptr;
  N_Vector y_ = nullptr;
  N_Vector atol_ = nullptr;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver LS_ = nullptr;
  void* mem_ = nullptr;
  double t_ = 0.0;
  std::vector<double> out_;
};

/// Root of f in [lo, hi] by GSL's Brent solver, to a bracket of relative width rel_tol.
/// Requires f(lo) and f(hi) of opposite signs (or one of them zero); throws otherwise.
double brent_root(const std::function<double(double)>& f, double lo, double hi, double rel_tol, const char* who);

/// Doubles hi (from hi0) until f(hi) > 0, given f(lo) < 0; throws after 200 doublings.
double bracket_upward(const std::function<double(double)>& f, double hi0, const char* who);

}  // namespace cdm::oracles::detail
