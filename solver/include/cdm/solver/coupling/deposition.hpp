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
#include <cmath>
#include <cstddef>
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

/// The cells and weights of one particle, computed once and visited for every quantity
/// deposited or averaged there. Fixed-size: no allocation per particle.
/// When the gas is evaluated at the particles (coupling.drag_evaluation).
enum class DragEvaluation {
  every_step,  // every DEM step: gas velocity, ε_g, ∇P and K at the particle; reaction deposited
  gas_step     // at the first DEM step of each gas step; K(u_g − v) with the particle's current
               // v and the cached −V_p∇P at every step; the reaction deposited once per gas step
};
inline constexpr Keywords<DragEvaluation, 2> drag_evaluation_keywords{{{"every_step", DragEvaluation::every_step}, {"gas_step", DragEvaluation::gas_step}}};
inline const char* to_string(DragEvaluation e) { return keyword_of(drag_evaluation_keywords, e); }

/// Shared by the gas-particle force modules when they evaluate the gas once per gas step:
/// @c due is set at each gas step and cleared once the modules have evaluated.
struct GasStepClock {
  bool due = true;
};

class Stencil {
 public:
  static constexpr int max_local = 8;  // cell: 1, trilinear: 8 (2D: 4)
  static constexpr int max_axis = 64;  // gaussian: samples per axis

  /// Visit the (padded cell index, weight) pairs: f(index, w).
  template <class F>
  void for_each(F&& f) const {
    if (!separable_) {
      for (int k = 0; k < count_; ++k) f(idx_[k], w_[k]);
      return;
    }
    for (int k = 0; k < n_[2]; ++k)
      for (int j = 0; j < n_[1]; ++j) {
        const double wjk = wa_[1][j] * wa_[2][k];
        const std::size_t row = base_ + off_[1][j] + off_[2][k];
        for (int i = 0; i < n_[0]; ++i) f(row + off_[0][i], (wa_[0][i] * wjk) * inv_);
      }
  }

 private:
  friend class Deposition;
  void add(std::size_t i, double w) { idx_[count_] = i; w_[count_] = w; ++count_; }

  bool separable_ = false;
  // Local kernels: the pairs.
  int count_ = 0;
  std::size_t idx_[max_local];
  double w_[max_local];
  // Gaussian: the product of per-axis weights wa_ at per-axis offsets off_ from base_,
  // times the normalisation inv_.
  int n_[3] = {0, 0, 0};
  std::size_t base_ = 0;
  std::size_t off_[3][max_axis];
  double wa_[3][max_axis];
  double inv_ = 1.0;
};

class Deposition {
 public:
  Deposition(const fluid::StaggeredGrid& grid, Kernel kernel, double width);

  /// The stencil of the particle at @p x.
  void stencil(Vec3 x, Stencil& s) const;
  /// Visit the (cell index, weight) pairs of the particle at @p x: f(padded index, w),
  /// in the order stencil() lists them.
  template <class F>
  [[gnu::always_inline]] inline void for_each_weight(Vec3 x, F&& f) const {
    if (kernel_ == Kernel::trilinear) {
      for_each_trilinear(x, f);
      return;
    }
    Stencil s;
    stencil(x, s);
    s.for_each(f);
  }
  /// Kernel-weighted average of a cell-centred array at @p x.
  double average(const std::vector<double>& cells, Vec3 x) const;
  Kernel kernel() const { return kernel_; }
  double width() const { return sigma_; }

 private:
  /// Map a cell index along @p axis into the domain (wrap or reflect).
  int fold(int axis, int i) const {
    const int n = grid_->n(axis);
    return i >= 0 && i < n ? i : fold_outside(axis, i);
  }
  int fold_outside(int axis, int i) const;
  void holding_cell(const double f[3], Stencil& s) const;
  /// The trilinear kernel's pairs, computed in registers as they are visited: per axis
  /// the two neighbours, folded and scaled by the array strides, and their weights 1 − t
  /// and t (an axis the grid lacks, 2D's z, has one, of weight 1); pairs of weight 0 are
  /// skipped.
  template <class F>
  [[gnu::always_inline]] inline void for_each_trilinear(Vec3 x, F& f) const {
    const fluid::StaggeredGrid& g = *grid_;
    const double xs[3] = {x.x, x.y, x.z};
    const int dims = g.dims();
    std::size_t o[3][2] = {{0, 0}, {0, 0}, {0, 0}};
    double w[3][2] = {{1.0, 0.0}, {1.0, 0.0}, {1.0, 0.0}};
    for (int a = 0; a < dims; ++a) {
      // Fractional cell-centre coordinate: the centre of cell i at i.
      const double fa = (xs[a] - g.lo(a)) * g.inv_h(a) - 0.5;
      const int i0 = static_cast<int>(std::floor(fa));
      const double t = fa - i0;
      w[a][0] = 1 - t;
      w[a][1] = t;
      o[a][0] = static_cast<std::size_t>(fold(a, i0)) * stride_[a];
      o[a][1] = static_cast<std::size_t>(fold(a, i0 + 1)) * stride_[a];
    }
    const int kz = dims == 3 ? 2 : 1;
    for (int dk = 0; dk < kz; ++dk)
      for (int dj = 0; dj < 2; ++dj) {
        const std::size_t row = base_ + o[1][dj] + o[2][dk];
        for (int di = 0; di < 2; ++di) {
          const double wt = w[0][di] * w[1][dj] * w[2][dk];
          if (wt == 0.0) continue;
          f(row + o[0][di], wt);
        }
      }
  }

  const fluid::StaggeredGrid* grid_;
  std::size_t base_;       // the padded index of cell (0, 0, 0)
  std::size_t stride_[3];  // the padded arrays' strides along each axis
  Kernel kernel_;
  double sigma_;
};

}  // namespace cdm::coupling
