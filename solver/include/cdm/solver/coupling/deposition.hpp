#pragma once
/// @file deposition.hpp
/// @brief Particle quantities onto the gas grid and back (Garg et al. 2012 eq 32): the
/// kernel K(X_i, x_k) that spreads a particle's volume or force over cell centres, and
/// the same weights used to average a cell field at the particle.
///
///  - `cell`: all to the cell holding the centre (the paper's first method, eqs 33–35);
///  - `trilinear`: the 8 (2D: 4) nearest cell centres with trilinear weights ("cloud in
///    cell"); second order in the cell size, continuous as particles move;
///  - `gaussian`: exp(−r²/2σ²) over the cell centres within 3σ along each axis (a box-
///    truncated gaussian, evaluated as a product of 1D weights), σ set in the scene and
///    independent of the cell size, so refining the grid resolves the same smoothed field.
/// Weights always sum to one, so deposited volume and momentum are conserved exactly.
/// Across a periodic boundary weights wrap; a weight that would fall outside a wall is
/// reflected back into the cell it mirrors.
#include <vector>

#include "cdm/solver/fluid/staggered_grid.hpp"
#include "cdm/solver/keywords.hpp"

namespace cdm::coupling {

enum class Kernel { cell, trilinear, gaussian };
inline constexpr Keywords<Kernel, 3> kernel_keywords{{{"cell", Kernel::cell}, {"trilinear", Kernel::trilinear}, {"gaussian", Kernel::gaussian}}};
inline const char* to_string(Kernel k) { return keyword_of(kernel_keywords, k); }

/// The gas velocity a particle's drag sees (the "interpolate" method).
enum class SlipVelocity {
  interstitial,  // the face velocities u_f interpolated to the particle (Garg et al. eq 32)
  superficial    // the face fluxes ε_f u_f interpolated, divided by the particle's ε_g
};
inline constexpr Keywords<SlipVelocity, 2> slip_velocity_keywords{{{"interstitial", SlipVelocity::interstitial}, {"superficial", SlipVelocity::superficial}}};
inline const char* to_string(SlipVelocity s) { return keyword_of(slip_velocity_keywords, s); }

/// How drag couples particles and a solved gas (Garg et al. 2012 §2.2.3).
enum class CouplingMethod {
  cell_average,  // eqs 33–35: cell-centred gas velocity, cell-averaged solids velocity
  interpolate    // eqs 32, 36: gas velocity at each particle, forces deposited by a kernel
};
inline constexpr Keywords<CouplingMethod, 2> coupling_method_keywords{{{"interpolate", CouplingMethod::interpolate}, {"cell_average", CouplingMethod::cell_average}}};
inline const char* to_string(CouplingMethod m) { return keyword_of(coupling_method_keywords, m); }

class Deposition {
 public:
  Deposition(const fluid::StaggeredGrid& grid, Kernel kernel, double width);

  /// Visit the (cell index, weight) pairs of the particle at @p x: f(padded index, w).
  /// Thread-safe (the weights go to per-thread buffers); f must not call back into it.
  template <class F>
  void for_each_weight(Vec3 x, F&& f) const {
    thread_local std::vector<std::size_t> idx;
    thread_local std::vector<double> w;
    weights(x, idx, w);
    for (std::size_t k = 0; k < idx.size(); ++k) f(idx[k], w[k]);
  }
  /// Kernel-weighted average of a cell-centred array at @p x.
  double average(const std::vector<double>& cells, Vec3 x) const;
  Kernel kernel() const { return kernel_; }
  double width() const { return sigma_; }

 private:
  void weights(Vec3 x, std::vector<std::size_t>& idx, std::vector<double>& w) const;
  /// Map a cell index along @p axis into the domain (wrap or reflect); false if it leaves
  /// a non-periodic axis by more than the grid (never for the stencils used).
  int fold(int axis, int i) const;

  const fluid::StaggeredGrid* grid_;
  Kernel kernel_;
  double sigma_;
};

}  // namespace cdm::coupling
