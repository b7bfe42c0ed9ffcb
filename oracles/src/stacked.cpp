#include "cdm/oracles/stacked.hpp"

#include <cvode/cvode.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_permutation.h>
#include <gsl/gsl_vector.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace cdm::oracles {

namespace {

// z = [y1, y2, v1, v2]; z' = A z + b.
struct Linear {
  double A[4][4] = {};
  double b[4] = {};
};

double eta(double kn, double m_eff, double en) {
  const double pi = std::numbers::pi, l = std::log(en);
  return 2.0 * std::sqrt(m_eff * kn) * std::abs(l) / std::sqrt(pi * pi + l * l);
}

Linear build(const StackedParams& p) {
  const double pi = std::numbers::pi, d = 2.0 * p.radius, r = p.radius;
  const double m1 = p.rho_lower * pi * d * d * d / 6.0, m2 = p.rho_upper * pi * d * d * d / 6.0;
  const double e1w = eta(p.kn_wall, m1, p.en), e2w = eta(p.kn_wall, m2, p.en);
  const double e12 = eta(p.kn, m1 * m2 / (m1 + m2), p.en);
  const double kw = p.kn_wall, kn = p.kn, yw = p.y_wall_top;
  Linear L;
  L.A[0][2] = 1.0;
  L.A[1][3] = 1.0;
  L.A[2][0] = -(kw + kn) / m1;
  L.A[2][1] = kn / m1;
  L.A[2][2] = -(e1w + e12) / m1;
  L.A[2][3] = e12 / m1;
  L.b[2] = -p.g + kw * r / m1 - 2.0 * kn * r / m1;
  L.A[3][0] = kn / m2;
  L.A[3][1] = -(kw + kn) / m2;
  L.A[3][2] = e12 / m2;
  L.A[3][3] = -(e2w + e12) / m2;
  L.b[3] = -p.g - kw * (r - yw) / m2 + 2.0 * kn * r / m2;
  return L;
}

int rhs(sunrealtype, N_Vector z, N_Vector dz, void* user) {
  const Linear& L = *static_cast<const Linear*>(user);
  const double* zz = N_VGetArrayPointer(z);
  double* d = N_VGetArrayPointer(dz);
  for (int i = 0; i < 4; ++i) {
    double s = L.b[i];
    for (int j = 0; j < 4; ++j) s += L.A[i][j] * zz[j];
    d[i] = s;
  }
  return 0;
}

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("stacked_cvode: ") + what + " failed with flag " + std::to_string(flag));
}

}  // namespace

StackedSeries stacked_cvode(const StackedParams& p, const std::vector<double>& times, double rtol) {
  Linear L = build(p);
  StackedSeries out;
  SUNContext ctx = nullptr;
  check(SUNContext_Create(nullptr, &ctx), "SUNContext_Create");
  N_Vector z = N_VNew_Serial(4, ctx);
  N_Vector atol = N_VNew_Serial(4, ctx);
  double* zz = N_VGetArrayPointer(z);
  zz[0] = p.y1_0; zz[1] = p.y2_0; zz[2] = 0.0; zz[3] = 0.0;
  // Absolute tolerances scaled to the problem: positions ~ r, velocities ~ r w.
  const double d = 2.0 * p.radius;
  const double m2 = p.rho_upper * std::numbers::pi * d * d * d / 6.0;
  const double w = std::sqrt((p.kn + p.kn_wall) / m2);
  double* at = N_VGetArrayPointer(atol);
  const double atol_pos = rtol * 1e-3 * p.radius, atol_vel = atol_pos * w;
  at[0] = at[1] = atol_pos;
  at[2] = at[3] = atol_vel;
  void* mem = CVodeCreate(CV_BDF, ctx);
  const double t0 = 0.0;
  check(CVodeInit(mem, rhs, t0, z), "CVodeInit");
  check(CVodeSVtolerances(mem, rtol, atol), "CVodeSVtolerances");
  check(CVodeSetUserData(mem, &L), "CVodeSetUserData");
  check(CVodeSetMaxNumSteps(mem, 1000000), "CVodeSetMaxNumSteps");
  SUNMatrix A = SUNDenseMatrix(4, 4, ctx);
  SUNLinearSolver LS = SUNLinSol_Dense(z, A, ctx);
  check(CVodeSetLinearSolver(mem, LS, A), "CVodeSetLinearSolver");
  N_Vector y = N_VClone(z);
  double tcur = t0;
  for (double t : times) {
    const double* yy = N_VGetArrayPointer(z);
    if (t > tcur) {
      check(CVode(mem, t, y, &tcur, CV_NORMAL), "CVode");
      yy = N_VGetArrayPointer(y);
    } else if (tcur > t0) {
      yy = N_VGetArrayPointer(y);
    }
    out.t.push_back(t);
    out.y1.push_back(yy[0]);
    out.y2.push_back(yy[1]);
    out.v1.push_back(yy[2]);
    out.v2.push_back(yy[3]);
  }
  N_VDestroy(y);
  SUNLinSolFree(LS);
  SUNMatDestroy(A);
  CVodeFree(&mem);
  N_VDestroy(atol);
  N_VDestroy(z);
  SUNContext_Free(&ctx);
  out.accuracy = {rtol, atol_pos, "cvode-bdf-dense"};
  return out;
}

StackedSeries stacked_exact(const StackedParams& p, const std::vector<double>& times) {
  const Linear L = build(p);
  gsl_matrix* A = gsl_matrix_alloc(4, 4);
  gsl_matrix* LU = gsl_matrix_alloc(4, 4);
  gsl_matrix* At = gsl_matrix_alloc(4, 4);
  gsl_matrix* E = gsl_matrix_alloc(4, 4);
  gsl_vector* rhs_b = gsl_vector_alloc(4);
  gsl_vector* zeq = gsl_vector_alloc(4);
  gsl_permutation* perm = gsl_permutation_alloc(4);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) gsl_matrix_set(A, i, j, L.A[i][j]);
    gsl_vector_set(rhs_b, i, -L.b[i]);
  }
  // Equilibrium: A z_eq = -b.
  gsl_matrix_memcpy(LU, A);
  int sign = 0;
  gsl_linalg_LU_decomp(LU, perm, &sign);
  gsl_linalg_LU_solve(LU, perm, rhs_b, zeq);
  const double z0[4] = {p.y1_0, p.y2_0, 0.0, 0.0};
  StackedSeries out;
  for (double t : times) {
    gsl_matrix_memcpy(At, A);
    gsl_matrix_scale(At, t);
    gsl_linalg_exponential_ss(At, E, GSL_PREC_DOUBLE);
    double z[4];
    for (int i = 0; i < 4; ++i) {
      double s = gsl_vector_get(zeq, i);
      for (int j = 0; j < 4; ++j) s += gsl_matrix_get(E, i, j) * (z0[j] - gsl_vector_get(zeq, j));
      z[i] = s;
    }
    out.t.push_back(t);
    out.y1.push_back(z[0]);
    out.y2.push_back(z[1]);
    out.v1.push_back(z[2]);
    out.v2.push_back(z[3]);
  }
  gsl_permutation_free(perm);
  gsl_vector_free(zeq);
  gsl_vector_free(rhs_b);
  gsl_matrix_free(E);
  gsl_matrix_free(At);
  gsl_matrix_free(LU);
  gsl_matrix_free(A);
  out.accuracy = {1e-15, 0.0, "gsl-matrix-exponential"};
  return out;
}

}  // namespace cdm::oracles
