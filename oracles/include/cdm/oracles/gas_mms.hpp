#pragma once
/// @file gas_mms.hpp
/// @brief A manufactured solution of the volume-averaged incompressible gas equations
/// (Garg et al. 2012 eqs 1–4 at constant density, "model A"):
///   ∂ε/∂t + ∇·(ε u) = S_m,
///   ρ[∂(εu)/∂t + ∇·(ε u u)] = −ε∇p + ∇·(εμ∇u) + S,
/// on the periodic unit square, with c(t) = 1 + sin(t)/2, k = 2π:
///   u = u0 + c sin kx cos ky,  v = v0 − c cos kx sin ky,  p = p0 c cos kx cos ky,
///   ε = 1 − a − b sin kx cos ky.
/// The sources S_m, S = (S_x, S_y) are derived symbolically by
/// verification/cases/gas_mms/derive_sources.py (sympy) into src/gas_mms.cpp — from the
/// PDEs, never from the solver's discrete operators. Closed forms: exact to round-off.
namespace cdm::oracles {

struct GasMmsParams {
  double u0 = 0.5, v0 = 0.3;  // mean flow [m/s]
  double p0 = 0.2;            // pressure amplitude [Pa]
  double a = 0.0, b = 0.0;    // ε = 1 − a − b sin kx cos ky [-]
  double rho = 1.0;           // gas density [kg/m^3]
  double mu = 0.05;           // gas viscosity [Pa s]
};

struct GasMmsState {
  double u, v, p, eps;
};
struct GasMmsSources {
  double mass;        // S_m [1/s]
  double momentum_x;  // S_x [N/m^3]
  double momentum_y;  // S_y [N/m^3]
};

GasMmsState gas_mms_state(const GasMmsParams& q, double x, double y, double t);
GasMmsSources gas_mms_sources(const GasMmsParams& q, double x, double y, double t);

}  // namespace cdm::oracles
