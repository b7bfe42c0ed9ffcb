#pragma once
/// @file materials.hpp
/// @brief Materials (phases) and the pairwise contact parameters between them.
///
/// Damping from restitution, Garg et al. (2012) eq 29, for the pair's effective mass
/// m_eff = m_i m_j / (m_i + m_j) (m_eff = m_i against a wall):
///   eta_n = 2 sqrt(m_eff k_n) |ln e| / sqrt(pi^2 + ln^2 e) = 2 sqrt(m_eff k_n) * c(e).
/// Collision time (eq 28): t_col = pi (k_n/m_eff - eta_n^2/(4 m_eff^2))^(-1/2)
///                               = pi sqrt(m_eff / (k_n (1 - c^2))).
/// A pair may instead use the Hertz–Mindlin law (contact/hertz_mindlin.hpp), whose
/// parameters come from the two materials' Young's moduli and Poisson ratios.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "cdm/solver/contact/hertz_mindlin.hpp"
#include "cdm/solver/keywords.hpp"

namespace cdm {

/// The most materials a scene may define: a particle's material is held in one byte (the
/// store holds every particle's on every MPI process).
inline constexpr std::size_t max_materials = 256;

struct Material {
  std::string name;
  double density = 0.0;         // [kg/m^3]; 0 for a material used by walls only
  double youngs_modulus = 0.0;  // E [Pa]; 0 when not given (only Hertz–Mindlin pairs need it)
  double poisson_ratio = 0.0;   // nu [-]
  bool fixed = false;           // particles of this material never move (a packed bed's grains)
};

/// The force law of a pair of materials.
enum class ContactLaw : std::uint8_t { linear_spring_dashpot, hertz_mindlin };
inline constexpr Keywords<ContactLaw, 2> contact_law_keywords{
    {{"linear_spring_dashpot", ContactLaw::linear_spring_dashpot}, {"hertz_mindlin", ContactLaw::hertz_mindlin}}};
inline const char* to_string(ContactLaw law) { return keyword_of(contact_law_keywords, law); }
/// How a Hertz–Mindlin pair's dashpot follows from its restitution coefficient.
enum class HertzDamping : std::uint8_t { exact_restitution, tsuji };
inline constexpr Keywords<HertzDamping, 2> hertz_damping_keywords{
    {{"exact_restitution", HertzDamping::exact_restitution}, {"tsuji", HertzDamping::tsuji}}};
inline const char* to_string(HertzDamping d) { return keyword_of(hertz_damping_keywords, d); }

/// Contact parameters for one unordered pair of materials.
struct PairParams {
  ContactLaw law = ContactLaw::linear_spring_dashpot;
  double kn = 0.0;            // normal spring stiffness [N/m] (linear)
  double en = 1.0;            // normal restitution coefficient [-], in (0, 1]
  double kt_factor = 0.4;     // kt = kt_factor * kn [-] (paper default 2/5)
  double etat_factor = 0.5;   // eta_t = etat_factor * eta_n [-] (paper default 1/2)
  double mu = 0.0;            // Coulomb friction coefficient [-]
  double damping_factor = 0.0;  // c(en) = |ln en| / sqrt(pi^2 + ln^2 en) [-], derived (linear)
  // Hertz–Mindlin (law == hertz_mindlin)
  double e_star = 0.0;        // effective Young's modulus E* [Pa]
  double g_star = 0.0;        // effective shear modulus G* [Pa]
  HertzDamping hertz_damping = HertzDamping::exact_restitution;
  double hertz_alpha = 0.0;   // alpha in eta_n = alpha sqrt(m* K) delta^{1/4} [-], derived
  double etat_hertz_factor = 0.0;  // eta_t / eta_n = 2 sqrt(G*/E*) [-], derived
  // Rolling resistance (modules.rolling_resistance)
  double rolling_mu = 0.0;    // mu_r in M_r = mu_r R* |F_n| [-]
  bool defined = false;
};

/// c(e) = |ln e| / sqrt(pi^2 + ln^2 e), the damping ratio that gives restitution e.
inline double damping_ratio_from_restitution(double en) {
  const double l = std::log(en);
  return std::abs(l) / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
}

/// Effective mass [kg] of two free bodies of masses @p mi and @p mj.
inline double effective_mass(double mi, double mj) { return mi * mj / (mi + mj); }

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
  /// Store the pair's parameters and derive its damping (eq 29, or the Hertz α).
  void set(int a, int b, PairParams p) {
    p.damping_factor = damping_ratio_from_restitution(p.en);
    if (p.law == ContactLaw::hertz_mindlin) {
      p.hertz_alpha = hertz_alpha(p.en, p.hertz_damping);
      p.etat_hertz_factor = p.e_star > 0.0 ? 2.0 * std::sqrt(p.g_star / p.e_star) : 0.0;
      law_mask_ |= 2u;
    } else {
      law_mask_ |= 1u;
    }
    p.defined = true;
    p_[a * n_ + b] = p;
    p_[b * n_ + a] = p;
  }
  const PairParams& get(int a, int b) const { return p_[a * n_ + b]; }
  std::size_t size() const { return n_; }
  /// Whether any defined pair uses @p law.
  bool uses(ContactLaw law) const { return law_mask_ & (law == ContactLaw::hertz_mindlin ? 2u : 1u); }
  /// The Hertz dashpot's α for restitution @p en (contact/hertz_mindlin.hpp).
  static double hertz_alpha(double en, HertzDamping d) {
    return d == HertzDamping::tsuji ? contact::hertz_alpha_tsuji(en) : contact::hertz_alpha_exact(en);
  }

 private:
  std::size_t n_;
  std::vector<PairParams> p_;
  unsigned law_mask_ = 0;  // bit 0: some pair is linear, bit 1: some pair is Hertz–Mindlin
};

}  // namespace cdm
