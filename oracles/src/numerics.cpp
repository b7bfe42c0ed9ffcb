#include "numerics.hpp"

#include <cvode/cvode.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace cdm::oracles::detail {

Cvode::Cvode(OdeRhs rhs, const std::vector<double>& y0, double t0, double rtol, const std::vector<double>& atol,
             const char* who)
    : rhs_(std::move(rhs)), who_(who), n_(static_cast<int>(y0.size())), t_(t0), out_(y0) {
  check(SUNContext_Create(nullptr, &ctx_), "SUNContext_Create");
  y_ = N_VNew_Serial(n_, ctx_);
  atol_ = N_VNew_Serial(n_, ctx_);
  double* yy = N_VGetArrayPointer(y_);
  double* aa = N_VGetArrayPointer(atol_);
  for (int i = 0; i < n_; ++i) {
    yy[i] = y0[i];
    aa[i] = atol[i];
  }
  // BDF with a dense Newton solve: the drag relaxation can be much faster than the
  // motion it drives (small Stokes numbers), so the method must be stiffly stable.
  mem_ = CVodeCreate(CV_BDF, ctx_);
  if (mem_ == nullptr) throw std::runtime_error(std::string(who_) + ": CVodeCreate failed");
  check(CVodeInit(mem_, rhs_thunk, t0, y_), "CVodeInit");
  check(CVodeSVtolerances(mem_, rtol, atol_), "CVodeSVtolerances");
  check(CVodeSetUserData(mem_, this), "CVodeSetUserData");
  check(CVodeSetMaxNumSteps(mem_, 10000000), "CVodeSetMaxNumSteps");
  A_ = SUNDenseMatrix(n_, n_, ctx_);
  LS_ = SUNLinSol_Dense(y_, A_, ctx_);
  check(CVodeSetLinearSolver(mem_, LS_, A_), "CVodeSetLinearSolver");
}

Cvode::~Cvode() {
  SUNLinSolFree(LS_);
  SUNMatDestroy(A_);
  CVodeFree(&mem_);
  N_VDestroy(atol_);
  N_VDestroy(y_);
  SUNContext_Free(&ctx_);
}

int Cvode::rhs_thunk(sunrealtype t, N_Vector y, N_Vector dy, void* self) {
  const auto* c = static_cast<const Cvode*>(self);
  c->rhs_(t, N_VGetArrayPointer(y), N_VGetArrayPointer(dy));
  for (int i = 0; i < c->n_; ++i) {
    if (!std::isfinite(N_VGetArrayPointer(dy)[i])) return 1;  // recoverable: CVODE cuts the step
  }
  return 0;
}

void Cvode::check(int flag, const char* what) const {
  if (flag < 0) throw std::runtime_error(std::string(who_) + ": " + what + " failed with flag " + std::to_string(flag));
}

const std::vector<double>& Cvode::advance(double t) {
  if (t < t_) throw std::invalid_argument(std::string(who_) + ": output times must increase");
  if (t > t_) {
    double treached = t_;
    check(CVode(mem_, t, y_, &treached, CV_NORMAL), "CVode");
    t_ = t;
    const double* yy = N_VGetArrayPointer(y_);
    for (int i = 0; i < n_; ++i) out_[i] = yy[i];
  }
  return out_;
}

void Cvode::reinit(const std::vector<double>& y0, double t0) {
  double* yy = N_VGetArrayPointer(y_);
  for (int i = 0; i < n_; ++i) yy[i] = out_[i] = y0[i];
  t_ = t0;
  check(CVodeReInit(mem_, t0, y_), "CVodeReInit");
}

long Cvode::steps() const {
  long n = 0;
  CVodeGetNumSteps(mem_, &n);
  return n;
}

namespace {
double call(double x, void* params) { return (*static_cast<const std::function<double(double)>*>(params))(x); }
}  // namespace

double brent_root(const std::function<double(double)>& f, double lo, double hi, double rel_tol, const char* who) {
  const double flo = f(lo), fhi = f(hi);
  if (flo == 0.0) return lo;
  if (fhi == 0.0) return hi;
  if (!(std::isfinite(flo) && std::isfinite(fhi)) || (flo < 0.0) == (fhi < 0.0)) {
    throw std::runtime_error(std::string(who) + ": root not bracketed in [" + std::to_string(lo) + ", " +
                             std::to_string(hi) + "]");
  }
  gsl_function F;
  F.function = call;
  F.params = const_cast<std::function<double(double)>*>(&f);
  gsl_root_fsolver* s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  gsl_root_fsolver_set(s, &F, lo, hi);
  double x = 0.5 * (lo + hi);
  int status = GSL_CONTINUE;
  for (int it = 0; it < 500 && status == GSL_CONTINUE; ++it) {
    gsl_root_fsolver_iterate(s);
    x = gsl_root_fsolver_root(s);
    status = gsl_root_test_interval(gsl_root_fsolver_x_lower(s), gsl_root_fsolver_x_upper(s), 0.0, rel_tol);
  }
  gsl_root_fsolver_free(s);
  if (status != GSL_SUCCESS) throw std::runtime_error(std::string(who) + ": Brent root finding did not converge");
  return x;
}

double bracket_upward(const std::function<double(double)>& f, double hi0, const char* who) {
  double hi = hi0;
  for (int k = 0; k < 200; ++k, hi *= 2.0) {
    if (f(hi) > 0.0) return hi;
  }
  throw std::runtime_error(std::string(who) + ": could not bracket the root");
}

}  // namespace cdm::oracles::detail
