#pragma once
/// @file tolerance.hpp
/// @brief What an oracle was computed to, so every error table can say it.
#include <string>

namespace cdm::oracles {

struct OracleAccuracy {
  double rtol = 0.0;   // relative tolerance of the numerical method (0 for closed forms)
  double atol = 0.0;   // absolute tolerance (root finding in time [s], or ODE state)
  std::string method;  // e.g. "closed-form+gsl-brent", "cvode-bdf"
};

}  // namespace cdm::oracles
