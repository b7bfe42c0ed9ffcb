#include "cdm/oracles/hertz_impact.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cdm::oracles {

namespace {

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("hertz oracle: ") + what + " failed with flag " + std::to_string(flag));
}

double beta_fn(double a, double b) { return std::tgamma(a) * std::tgamma(b) / std::tgamma(a + b); }

// y = [δ, δ']; m* δ'' = −K δ^{3/2} − c δ^{1/4} δ' while δ > 0 (no force outside).
struct Rhs {
  double k_over_m;  // K/m*
  double c_over_m;  // α √(m* K)/m*
};

int rhs(sunrealtype, N_Vector y, N_Vector dy, void* user) {
  const Rhs& r = *static_cast<const Rhs*>(user);
  const double* yy = N_VGetArrayPointer(y);
  double* d = N_VGetArrayPointer(dy);
  const double x = std::max(yy[0], 0.0);
  const double q = std::sqrt(std::sqrt(x));  // δ^{1/4}
  d[0] = yy[1];
  d[1] = -r.k_over_m * x * q * q - r.c_over_m * q * yy[1];
  return 0;
}

// Roots: δ = 0 (end of contact, δ decreasing) and δ' = 0 (maximum compression).
int roots(sunrealtype, N_Vector y, sunrealtype* g, void*) {
  const double* yy = N_VGetArrayPointer(y);
  g[0] = yy[0];
  g[1] = yy[1];
  return 0;
}

/// A CVODE integrator of the contact from δ = 0, δ' = v, in units given by the caller.
class ContactOde {
 public:
  ContactOde(Rhs r, double v, double atol_x, double atol_v, double rtol) : r_(r) {
    check(SUNContext_Create(nullptr, &ctx_), "SUNContext_Create");
    y_ = N_VNew_Serial(2, ctx_);
    atol_ = N_VNew_Serial(2, ctx_);
    double* yy = N_VGetArrayPointer(y_);
    yy[0] = 0.0;
    yy[1] = v;
    double* at = N_VGetArrayPointer(atol_);
    at[0] = atol_x;
    at[1] = atol_v;
    mem_ = CVodeCreate(CV_ADAMS, ctx_);
    check(CVodeInit(mem_, rhs, 0.0, y_), "CVodeInit");
    check(CVodeSVtolerances(mem_, rtol, atol_), "CVodeSVtolerances");
    check(CVodeSetUserData(mem_, &r_), "CVodeSetUserData");
    check(CVodeSetMaxNumSteps(mem_, 10000000), "CVodeSetMaxNumSteps");
    A_ = SUNDenseMatrix(2, 2, ctx_);
    LS_ = SUNLinSol_Dense(y_, A_, ctx_);
    check(CVodeSetLinearSolver(mem_, LS_, A_), "CVodeSetLinearSolver");
    check(CVodeRootInit(mem_, 2, roots), "CVodeRootInit");
    int dir[2] = {-1, -1};  // δ falling through 0; δ' falling through 0
    check(CVodeSetRootDirection(mem_, dir), "CVodeSetRootDirection");
    check(CVodeSetNoInactiveRootWarn(mem_), "CVodeSetNoInactiveRootWarn");
    out_ = N_VClone(y_);
  }
  ~ContactOde() {
    N_VDestroy(out_);
    SUNLinSolFree(LS_);
    SUNMatDestroy(A_);
    CVodeFree(&mem_);
    N_VDestroy(atol_);
    N_VDestroy(y_);
    SUNContext_Free(&ctx_);
  }
  ContactOde(const ContactOde&) = delete;
  ContactOde& operator=(const ContactOde&) = delete;

  /// Advance towards @p tout; stops early at a root. Returns the time reached.
  double advance(double tout, bool& end_of_contact, bool& max_compression) {
    double t = 0.0;
    const int flag = CVode(mem_, tout, out_, &t, CV_NORMAL);
    check(flag, "CVode");
    end_of_contact = max_compression = false;
    if (flag == CV_ROOT_RETURN) {
      int found[2] = {0, 0};
      check(CVodeGetRootInfo(mem_, found), "CVodeGetRootInfo");
      end_of_contact = found[0] != 0;
      max_compression = found[1] != 0;
    }
    return t;
  }
  const double* state() const { return N_VGetArrayPointer(out_); }

 private:
  Rhs r_;
  SUNContext ctx_ = nullptr;
  N_Vector y_ = nullptr, atol_ = nullptr, out_ = nullptr;
  void* mem_ = nullptr;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver LS_ = nullptr;
};

}  // namespace

double hertz_effective_modulus(double e1, double nu1, double e2, double nu2) {
  return 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2);
}

HertzClosedForm hertz_closed_form(const HertzImpactParams& p) {
  HertzClosedForm c;
  const double k = 4.0 / 3.0 * p.e_star * std::sqrt(p.r_eff);
  c.max_overlap = std::pow(15.0 * p.m_eff * p.v * p.v / (16.0 * p.e_star * std::sqrt(p.r_eff)), 0.4);
  c.max_force = k * std::pow(c.max_overlap, 1.5);
  c.contact_time = 2.0 * c.max_overlap / p.v * 0.4 * beta_fn(0.4, 0.5);
  return c;
}

HertzSeries hertz_impact_cvode(const HertzImpactParams& p, const std::vector<double>& times, double rtol) {
  const double k = 4.0 / 3.0 * p.e_star * std::sqrt(p.r_eff);
  const Rhs r{k / p.m_eff, p.alpha * std::sqrt(p.m_eff * k) / p.m_eff};
  // Absolute tolerances scaled to the problem: overlaps ~ δ_max, speeds ~ v.
  const double dmax = hertz_closed_form(p).max_overlap;
  const double atol_x = rtol * 1e-3 * dmax, atol_v = rtol * 1e-3 * p.v;
  ContactOde ode(r, p.v, atol_x, atol_v, rtol);
  HertzSeries s;
  s.overlap.assign(times.size(), 0.0);
  s.force.assign(times.size(), 0.0);
  bool ended = false;
  double t_reached = 0.0;
  auto force_of = [&](double x, double xd) {
    const double q = std::sqrt(std::sqrt(std::max(x, 0.0)));
    return p.m_eff * (r.k_over_m * std::max(x, 0.0) * q * q + r.c_over_m * q * xd);
  };
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    if (t <= 0.0 || ended) continue;
    while (!ended && t_reached < t) {
      bool end = false, top = false;
      t_reached = ode.advance(t, end, top);
      if (top) s.max_overlap = ode.state()[0];
      if (end) {
        ended = true;
        s.contact_time = t_reached;
        s.exit_speed = -ode.state()[1];
      }
    }
    if (!ended || t_reached >= t) {
      s.overlap[i] = ode.state()[0];
      s.force[i] = force_of(ode.state()[0], ode.state()[1]);
    }
  }
  // Integrate to the end of contact even when the requested times stop earlier.
  while (!ended) {
    bool end = false, top = false;
    t_reached = ode.advance(t_reached + 10.0 * hertz_closed_form(p).contact_time, end, top);
    if (top) s.max_overlap = ode.state()[0];
    if (end) {
      ended = true;
      s.contact_time = t_reached;
      s.exit_speed = -ode.state()[1];
    }
  }
  s.accuracy = {rtol, atol_x, "cvode-adams-dense+roots"};
  return s;
}

double hertz_restitution(double alpha, OracleAccuracy* accuracy, double rtol) {
  const double atol = rtol * 1e-3;
  ContactOde ode(Rhs{1.0, alpha}, 1.0, atol, atol, rtol);
  double t = 0.0;
  for (int guard = 0; guard < 1000; ++guard) {
    bool end = false, top = false;
    t = ode.advance(t + 1e3, end, top);
    if (end) {
      if (accuracy) *accuracy = {rtol, atol, "cvode-adams-dense+roots(nondimensional)"};
      return -ode.state()[1];
    }
  }
  throw std::runtime_error("hertz_restitution: the contact did not end (alpha = " + std::to_string(alpha) + ")");
}

}  // namespace cdm::oracles
