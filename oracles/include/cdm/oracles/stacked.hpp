#pragma once
/// @file stacked.hpp
/// @brief Two stacked particles compressed between two walls: Garg et al. (2012),
/// App. C, with the paper's F12 typo fixed (its spring is kn):
///   y1'' = −g − (kw/m1)(y1 − r) − (η1w/m1) y1' − (kn/m1)(2r − (y2 − y1)) − (η12/m1)(y1' − y2')
///   y2'' = −g − (kw/m2)(r − (yw − y2)) − (η2w/m2) y2' + (kn/m2)(2r − (y2 − y1)) + (η12/m2)(y1' − y2')
/// each η from eq 29 with its own effective mass (m1, m2, m1 m2/(m1 + m2)).
/// stacked_cvode integrates it with SUNDIALS CVODE (BDF, dense Newton, rtol 1e-12);
/// stacked_exact solves the same linear constant-coefficient system exactly,
/// z(t) = z_eq + exp(A t)(z0 − z_eq), with GSL's matrix exponential — a second,
/// independent method for cross-checking the first.
#include <vector>

#include "cdm/oracles/tolerance.hpp"

namespace cdm::oracles {

struct StackedParams {
  double radius;      // r, both particles [m]
  double rho_lower;   // [kg/m^3]
  double rho_upper;   // [kg/m^3]
  double kn;          // particle-particle stiffness [N/m]
  double kn_wall;     // particle-wall stiffness, both walls [N/m]
  double en;          // restitution, all three contacts
  double g;           // gravity magnitude [m/s^2]
  double y_wall_top;  // upper wall position yw [m] (lower wall at 0)
  double y1_0, y2_0;  // initial centre heights [m], both at rest
};

struct StackedSeries {
  std::vector<double> t, y1, y2, v1, v2;
  OracleAccuracy accuracy;
};

/// CVODE (BDF) solution at exactly the requested increasing times.
StackedSeries stacked_cvode(const StackedParams& p, const std::vector<double>& times, double rtol = 1e-12);
/// Exact solution (matrix exponential) at the requested times.
StackedSeries stacked_exact(const StackedParams& p, const std::vector<double>& times);

}  // namespace cdm::oracles
