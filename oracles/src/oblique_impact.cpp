#include "cdm/oracles/oblique_impact.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace cdm::oracles {

namespace {

void check(int flag, const char* what) {
  if (flag < 0)
    throw std::runtime_error(std::string("oblique oracle: ") + what + " failed with flag " + std::to_string(flag));
}

struct Model {
  double R, m, I, K, g_star, mu, c;  // c = μ E*/(6 G*)
  bool slip = false;
  double s = 1.0;  // slip sign
};

// y = [δ, w = δ', v_t, Ω, ξ]; Ω is the spin in the sense that rolls the sphere forward
// (u = v_t − L Ω is the slip of the contact point, L = R − δ).
double friction(const Model& md, const double* y) {
  const double d = std::max(y[0], 0.0);
  if (md.slip) return -md.s * md.mu * md.K * d * std::sqrt(d);
  return -8.0 * md.g_star * std::sqrt(md.R * d) * y[4];
}

int rhs(sunrealtype, N_Vector yv, N_Vector dyv, void* user) {
  const Model& md = *static_cast<const Model*>(user);
  const double* y = N_VGetArrayPointer(yv);
  double* dy = N_VGetArrayPointer(dyv);
  const double d = std::max(y[0], 0.0);
  const double L = md.R - y[0];
  const double ft = friction(md, y);
  const double u = y[2] - L * y[3];
  dy[0] = y[1];
  dy[1] = -md.K * d * std::sqrt(d) / md.m;
  dy[2] = ft / md.m;
  dy[3] = -L * ft / md.I;
  dy[4] = md.slip ? md.s * md.c * y[1] : u;
  return 0;
}

int roots(sunrealtype, N_Vector yv, sunrealtype* g, void* user) {
  const Model& md = *static_cast<const Model*>(user);
  const double* y = N_VGetArrayPointer(yv);
  g[0] = y[0];
  if (md.slip) {
    const double u = y[2] - (md.R - y[0]) * y[3];
    g[1] = md.s * (u - md.c * y[1]);  // falls through 0: the spring can keep up again
  } else {
    g[1] = y[4] * y[4] - md.c * md.c * y[0] * y[0];  // rises through 0: |ξ| reaches the limit
  }
  return 0;
}

double beta_fn(double a, double b) { return std::tgamma(a) * std::tgamma(b) / std::tgamma(a + b); }

}  // namespace

ObliqueResult oblique_impact_cvode(const ObliqueParams& p, double rtol) {
  const double pi = std::numbers::pi;
  const double e_star = 1.0 / ((1.0 - p.nu_particle * p.nu_particle) / p.e_particle +
                               (1.0 - p.nu_wall * p.nu_wall) / p.e_wall);
  const double g_p = p.e_particle / (2.0 * (1.0 + p.nu_particle)), g_w = p.e_wall / (2.0 * (1.0 + p.nu_wall));
  const double g_star = 1.0 / ((2.0 - p.nu_particle) / g_p + (2.0 - p.nu_wall) / g_w);
  Model md;
  md.R = p.radius;
  md.m = p.density * 4.0 / 3.0 * pi * p.radius * p.radius * p.radius;
  md.I = 0.4 * md.m * p.radius * p.radius;
  md.K = 4.0 / 3.0 * e_star * std::sqrt(p.radius);
  md.g_star = g_star;
  md.mu = p.mu;
  md.c = p.mu * e_star / (6.0 * g_star);
  const double th = p.angle_deg * pi / 180.0;
  const double vn = p.speed * std::cos(th), vt = p.speed * std::sin(th);
  // Start: slides at once if the spring would outrun the Coulomb limit (see header).
  md.slip = std::abs(vt) > md.c * vn;
  md.s = vt >= 0.0 ? 1.0 : -1.0;
  bool ever_stuck = !md.slip;

  SUNContext ctx = nullptr;
  check(SUNContext_Create(nullptr, &ctx), "SUNContext_Create");
  N_Vector y = N_VNew_Serial(5, ctx), atol = N_VNew_Serial(5, ctx);
  double* yy = N_VGetArrayPointer(y);
  yy[0] = 0.0; yy[1] = vn; yy[2] = vt; yy[3] = 0.0; yy[4] = 0.0;
  // Scales: δ_max for lengths, the impact speed for speeds, speed/R for spin.
  const double dmax = std::pow(15.0 * md.m * vn * vn / (16.0 * e_star * std::sqrt(p.radius)), 0.4);
  const double ax = rtol * 1e-3 * dmax, av = rtol * 1e-3 * p.speed;
  double* at = N_VGetArrayPointer(atol);
  at[0] = ax; at[1] = av; at[2] = av; at[3] = av / p.radius; at[4] = ax;
  void* mem = CVodeCreate(CV_ADAMS, ctx);
  check(CVodeInit(mem, rhs, 0.0, y), "CVodeInit");
  check(CVodeSVtolerances(mem, rtol, atol), "CVodeSVtolerances");
  check(CVodeSetUserData(mem, &md), "CVodeSetUserData");
  check(CVodeSetMaxNumSteps(mem, 10000000), "CVodeSetMaxNumSteps");
  SUNMatrix A = SUNDenseMatrix(5, 5, ctx);
  SUNLinearSolver LS = SUNLinSol_Dense(y, A, ctx);
  check(CVodeSetLinearSolver(mem, LS, A), "CVodeSetLinearSolver");
  check(CVodeRootInit(mem, 2, roots), "CVodeRootInit");
  check(CVodeSetNoInactiveRootWarn(mem), "CVodeSetNoInactiveRootWarn");
  auto set_dirs = [&] {
    int dir[2] = {-1, md.slip ? -1 : +1};
    check(CVodeSetRootDirection(mem, dir), "CVodeSetRootDirection");
  };
  set_dirs();

  N_Vector out = N_VClone(y);
  const double t_far = 10.0 * 2.87 * std::pow(md.m * md.m / (p.radius * e_star * e_star * vn), 0.2);
  double t = 0.0;
  int switches = 0;
  bool ended = false;
  while (!ended) {
    const int flag = CVode(mem, t_far, out, &t, CV_NORMAL);
    check(flag, "CVode");
    if (flag != CV_ROOT_RETURN) throw std::runtime_error("oblique oracle: the contact did not end");
    int found[2] = {0, 0};
    check(CVodeGetRootInfo(mem, found), "CVodeGetRootInfo");
    if (found[0]) { ended = true; break; }
    double* o = N_VGetArrayPointer(out);
    if (md.slip) {
      md.slip = false;  // stick: ξ continues from the limit value s c δ
      ever_stuck = true;
    } else {
      md.slip = true;
      md.s = o[4] >= 0.0 ? 1.0 : -1.0;  // the spring pulls against ξ: slip along ξ
      o[4] = md.s * md.c * o[0];
    }
    ++switches;
    if (switches > 10000) throw std::runtime_error("oblique oracle: too many stick/slip switches");
    check(CVodeReInit(mem, t, out), "CVodeReInit");
    set_dirs();
  }
  const double* o = N_VGetArrayPointer(out);
  ObliqueResult r;
  r.vn_after = -o[1];
  r.vt_after = o[2];
  r.omega = o[3];
  r.et = o[2] / vt;
  r.contact_time = t;
  r.slid_throughout = !ever_stuck;
  r.switches = switches;
  r.accuracy = {rtol, ax, "cvode-adams-dense+roots"};
  N_VDestroy(out);
  SUNLinSolFree(LS);
  SUNMatDestroy(A);
  CVodeFree(&mem);
  N_VDestroy(atol);
  N_VDestroy(y);
  SUNContext_Free(&ctx);
  return r;
}

ObliqueSliding oblique_sliding_closed_form(const ObliqueParams& p) {
  const double pi = std::numbers::pi;
  const double th = p.angle_deg * pi / 180.0;
  const double vn = p.speed * std::cos(th);
  const double e_star = 1.0 / ((1.0 - p.nu_particle * p.nu_particle) / p.e_particle +
                               (1.0 - p.nu_wall * p.nu_wall) / p.e_wall);
  const double m = p.density * 4.0 / 3.0 * pi * p.radius * p.radius * p.radius;
  const double dmax = std::pow(15.0 * m * vn * vn / (16.0 * e_star * std::sqrt(p.radius)), 0.4);
  const double dbar = dmax * beta_fn(1.4, 0.5) / 2.0;
  ObliqueSliding s;
  s.et = 1.0 - 2.0 * p.mu / std::tan(th);
  s.omega_rigid = 5.0 * p.mu * vn / p.radius;
  s.omega_lever = 5.0 * p.mu * vn * (p.radius - dbar) / (p.radius * p.radius);
  return s;
}

}  // namespace cdm::oracles
