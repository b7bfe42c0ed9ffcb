#pragma once
/// @file materials.hpp
/// @brief Materials (phases) and the pairwise contact parameters between them.
///
/// Damping from restitution, Garg et al. (2012) eq 29, for the pair's effective mass
/// m_eff = m_i m_j / (m_i + m_j) (m_eff = m_i against a wall):
///   eta_n = 2 sqrt(m_eff k_n) |ln e| / sqrt(pi^2 + ln^2 e) = 2 sqrt(m_eff k_n) * c(e).
/// Collision time (eq 28): t_col = pi (k_n/m_eff - eta_n^2/(4 m_eff^2))^(-1/2)
///                               = pi sqrt(m_eff / (k_n (1 - c^2))).
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace cdm {

struct Material {
  std::string name;
  double density = 0.0;  // [kg/m^3]; 0 for a material used by walls only
  bool fixed = false;    // particles of this material never move (a packed bed's grains)
};

/// Contact parameters for one unordered pair of materials.
struct PairParams {
  double kn = 0.0;            // normal spring stiffness [N/m]
  double en = 1.0;            // normal restitution coefficient [-], in (0, 1]
  double kt_factor = 0.4;     // kt = kt_factor * kn [-] (paper default 2/5)
  double etat_factor = 0.5;   // eta_t = etat_factor * eta_n [-] (paper default 1/2)
  double mu = 0.0;            // Coulomb friction coefficient [-]
  double damping_factor = 0.0;  // c(en) = |ln en| / sqrt(pi^2 + ln^2 en) [-], derived
  bool defined = false;
};

/// c(e) = |ln e| / sqrt(pi^2 + ln^2 e), the damping ratio that gives restitution e.
inline double damping_ratio_from_restitution(double en) {
  const double l = std::log(en);
  return std::abs(l) / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
}

/// Normal dashpot coefficient eta_n [kg/s] for effective mass m_eff (eq 29).
inline double normal_damping(const PairParams& p, double m_eff) {
  return 2.0 * std::sqrt(m_eff * p.kn) * p.damping_factor;
}

/// Damped collision time [s] for effective mass m_eff (eq 28).
inline double collision_time(const PairParams& p, double m_eff) {
  const double c = p.damping_factor;
  return std::numbers::pi * std::sqrt(m_eff / (p.kn * (1.0 - c * c)));
}

/// Symmetric table of pair parameters over all materials.
class PairTable {
 public:
  explicit PairTable(std::size_t n_materials = 0) : n_(n_materials), p_(n_materials * n_materials) {}
  void set(int a, int b, PairParams p) {
    p.damping_factor = damping_ratio_from_restitution(p.en);
    p.defined = true;
    p_[a * n_ + b] = p;
    p_[b * n_ + a] = p;
  }
  const PairParams& get(int a, int b) const { return p_[a * n_ + b]; }
  std::size_t size() const { return n_; }

 private:
  std::size_t n_;
  std::vector<PairParams> p_;
};

}  // namespace cdm
