#include "cdm/oracles/vortex_advection.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace cdm::oracles {

namespace {

struct Field {
  VortexParams p;
  std::size_t n;
};

// One tracer per 2 (or 3) entries of the state: independent ODEs in one system.
int rhs(sunrealtype t, N_Vector s, N_Vector ds, void* user) {
  const Field& f = *static_cast<const Field*>(user);
  constexpr double pi = std::numbers::pi;
  const double c = f.p.amplitude * std::cos(pi * t / f.p.period), L = f.p.length;
  const double* q = N_VGetArrayPointer(s);
  double* d = N_VGetArrayPointer(ds);
  const std::size_t dim = f.p.three_d ? 3 : 2;
  for (std::size_t i = 0; i < f.n; ++i) {
    const double xi = q[dim * i] / L, eta = q[dim * i + 1] / L;
    const double sx = std::sin(pi * xi), sy = std::sin(pi * eta);
    if (!f.p.three_d) {
      d[2 * i] = 2.0 * sx * sx * std::sin(2.0 * pi * eta) * c;
      d[2 * i + 1] = -std::sin(2.0 * pi * xi) * sy * sy * c;
    } else {
      const double zeta = q[3 * i + 2] / L, sz = std::sin(pi * zeta);
      const double s2x = std::sin(2.0 * pi * xi), s2y = std::sin(2.0 * pi * eta), s2z = std::sin(2.0 * pi * zeta);
      d[3 * i] = 2.0 * sx * sx * s2y * s2z * c;
      d[3 * i + 1] = -s2x * sy * sy * s2z * c;
      d[3 * i + 2] = -s2x * s2y * sz * sz * c;
    }
  }
  return 0;
}

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("vortex_tracers: ") + what + " failed with flag " + std::to_string(flag));
}

}  // namespace

TracerPaths vortex_tracers(const VortexParams& p, const std::vector<double>& x0, const std::vector<double>& y0,
                           const std::vector<double>& z0, const std::vector<double>& times, double rtol) {
  Field f{p, x0.size()};
  const std::size_t dim = p.three_d ? 3 : 2;
  SUNContext ctx = nullptr;
  check(SUNContext_Create(nullptr, &ctx), "SUNContext_Create");
  N_Vector s = N_VNew_Serial(static_cast<sunindextype>(dim * f.n), ctx);
  double* q = N_VGetArrayPointer(s);
  for (std::size_t i = 0; i < f.n; ++i) {
    q[dim * i] = x0[i];
    q[dim * i + 1] = y0[i];
    if (dim == 3) q[dim * i + 2] = z0[i];
  }
  const double atol = rtol * p.length;
  void* mem = CVodeCreate(CV_ADAMS, ctx);
  check(CVodeInit(mem, rhs, 0.0, s), "CVodeInit");
  check(CVodeSStolerances(mem, rtol, atol), "CVodeSStolerances");
  check(CVodeSetUserData(mem, &f), "CVodeSetUserData");
  check(CVodeSetMaxNumSteps(mem, 10000000), "CVodeSetMaxNumSteps");
  SUNNonlinearSolver nls = SUNNonlinSol_FixedPoint(s, 0, ctx);
  check(CVodeSetNonlinearSolver(mem, nls), "CVodeSetNonlinearSolver");
  N_Vector y = N_VClone(s);
  N_VScale(1.0, s, y);
  TracerPaths out;
  double tcur = 0.0;
  for (double t : times) {
    if (t > tcur) check(CVode(mem, t, y, &tcur, CV_NORMAL), "CVode");
    const double* yy = N_VGetArrayPointer(y);
    std::vector<double> xs(f.n), ys(f.n), zs(f.n);
    for (std::size_t i = 0; i < f.n; ++i) {
      xs[i] = yy[dim * i];
      ys[i] = yy[dim * i + 1];
      zs[i] = dim == 3 ? yy[dim * i + 2] : z0[i];
    }
    out.x.push_back(std::move(xs));
    out.y.push_back(std::move(ys));
    out.z.push_back(std::move(zs));
  }
  N_VDestroy(y);
  SUNNonlinSolFree(nls);
  CVodeFree(&mem);
  N_VDestroy(s);
  SUNContext_Free(&ctx);
  out.accuracy = {rtol, atol, "cvode-adams-fixedpoint"};
  return out;
}

}  // namespace cdm::oracles
