// The staggered grid and the two interpolation schemes: exact for linear fields (both),
// second order for smooth fields (both), boundary ghost layers that put a no-slip wall's
// velocity at zero and make periodic fields continuous across the seam.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "cdm/solver/fluid/interpolation.hpp"
#include "cdm/solver/fluid/staggered_grid.hpp"

namespace {

using namespace cdm;
using namespace cdm::fluid;

using Field = std::function<Vec3(Vec3)>;

GridSpec box(int n, bool two_d, BoundaryKind kind) {
  GridSpec g;
  g.lo = {0.0, 0.0, 0.0};
  g.hi = {1.0, 2.0, two_d ? 0.1 : 1.5};
  g.cells = {n, 2 * n, two_d ? 1 : n + n / 2};
  g.two_d = two_d;
  for (int f = 0; f < 6; ++f) g.faces[f].kind = (two_d && f >= 4) ? BoundaryKind::periodic : kind;
  return g;
}

struct Sampled {
  StaggeredGrid grid;
  std::vector<double> u, v, w;
  Sampled(const GridSpec& spec, const Field& f) : grid(spec) {
    u = grid.make_array();
    v = grid.make_array();
    w = grid.make_array();
    auto fill = [&](std::vector<double>& a, Staggering s, double Vec3::*c) {
      for (int k = 0; k < grid.samples(s, 2); ++k)
        for (int j = 0; j < grid.samples(s, 1); ++j)
          for (int i = 0; i < grid.samples(s, 0); ++i) a[grid.at(i, j, k)] = f(grid.position(s, i, j, k)).*c;
    };
    fill(u, Staggering::u, &Vec3::x);
    fill(v, Staggering::v, &Vec3::y);
    if (!spec.two_d) fill(w, Staggering::w, &Vec3::z);
    grid.fill_velocity_ghosts(u, v, w);
  }
};

// Largest interpolation error over random points at least @p margin from the walls.
double max_error(const GridSpec& spec, InterpolationScheme scheme, const Field& f, double margin, int points = 400) {
  Sampled s(spec, f);
  VectorInterpolator in(s.grid, scheme);
  in.update(s.u, s.v, s.w);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  double err = 0.0;
  for (int p = 0; p < points; ++p) {
    Vec3 x{margin + U(rng) * (spec.hi.x - 2 * margin), margin + U(rng) * (spec.hi.y - 2 * margin),
           spec.two_d ? 0.05 : margin + U(rng) * (spec.hi.z - 2 * margin)};
    const Vec3 d = in.at(x) - f(x);
    err = std::max({err, std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  }
  return err;
}

TEST(Interpolation, ExactForLinearFields) {
  // A linear field is reproduced exactly in the interior by both schemes (trilinear
  // weights sum to one; corner averaging and quadratic Lagrange are exact for lines).
  for (bool d2 : {true, false}) {
    const Field lin = [d2](Vec3 x) {
      return Vec3{0.3 + 1.1 * x.x - 0.7 * x.y + (d2 ? 0.0 : 0.4 * x.z), -0.2 + 0.5 * x.x + 0.9 * x.y - (d2 ? 0.0 : 0.3 * x.z),
                  d2 ? 0.0 : 0.1 - 0.6 * x.x + 0.2 * x.y + 0.8 * x.z};
    };
    for (auto scheme : {InterpolationScheme::trilinear, InterpolationScheme::paper_lagrange2})
      EXPECT_LT(max_error(box(8, d2, BoundaryKind::free_slip), scheme, lin, 0.2), 1e-13)
          << (d2 ? "2D " : "3D ") << to_string(scheme);
  }
}

TEST(Interpolation, SecondOrderForSmoothPeriodicFields) {
  for (bool d2 : {true, false}) {
    const Field f = [d2](Vec3 x) {
      const double a = 2 * M_PI * x.x, b = M_PI * x.y, c = d2 ? 0.0 : 4 * M_PI * x.z / 3;
      return Vec3{std::sin(a) * std::cos(b) * std::cos(c), std::cos(a) * std::sin(b) + std::sin(c),
                  d2 ? 0.0 : std::cos(a + b) * std::sin(c)};
    };
    for (auto scheme : {InterpolationScheme::trilinear, InterpolationScheme::paper_lagrange2}) {
      const double e1 = max_error(box(d2 ? 16 : 8, d2, BoundaryKind::periodic), scheme, f, 0.0);
      const double e2 = max_error(box(d2 ? 32 : 16, d2, BoundaryKind::periodic), scheme, f, 0.0);
      const double e3 = max_error(box(d2 ? 64 : 32, d2, BoundaryKind::periodic), scheme, f, 0.0);
      const double order = std::log2(e1 / e3) / 2.0;
      EXPECT_GT(order, 1.8) << (d2 ? "2D " : "3D ") << to_string(scheme) << ": errors " << e1 << " " << e2 << " " << e3;
      EXPECT_LT(order, 2.3) << "second order, not better: the test is resolving the scheme";
    }
  }
}

TEST(Interpolation, NoSlipWallVelocityIsZeroAndPeriodicSeamIsContinuous) {
  // A field vanishing on the walls (like the vortex of Garg et al. eq 43): at the wall the
  // odd mirror of the tangential component gives zero to second order, the normal
  // component is zero on the wall face itself.
  const Field f = [](Vec3 x) {
    return Vec3{std::sin(M_PI * x.x) * std::sin(M_PI * x.y / 2), std::sin(M_PI * x.x) * std::sin(M_PI * x.y / 2), 0.0};
  };
  for (auto scheme : {InterpolationScheme::trilinear, InterpolationScheme::paper_lagrange2}) {
    double prev = 0.0;
    for (int n : {16, 32, 64}) {
      Sampled s(box(n, true, BoundaryKind::no_slip), f);
      VectorInterpolator in(s.grid, scheme);
      in.update(s.u, s.v, s.w);
      double wall = 0.0;
      for (int k = 0; k <= 20; ++k) {
        const double t = 0.05 + 0.045 * k;
        for (Vec3 x : {Vec3{0.0, 2 * t, 0.05}, Vec3{1.0, 2 * t, 0.05}, Vec3{t, 0.0, 0.05}, Vec3{t, 2.0, 0.05}}) {
          const Vec3 u = in.at(x);
          wall = std::max({wall, std::abs(u.x), std::abs(u.y)});
        }
      }
      EXPECT_LT(wall, 2.0 / (n * n)) << to_string(scheme) << " n=" << n;
      if (prev > 0) {
        EXPECT_GT(prev / wall, 3.0) << to_string(scheme) << ": wall velocity must fall as h^2";
      }
      prev = wall;
    }
  }
  // Periodic: the value at x = lo equals the value at x = hi (the same point).
  const Field g = [](Vec3 x) { return Vec3{std::cos(2 * M_PI * x.x), std::sin(M_PI * x.y), 0.0}; };
  Sampled s(box(16, true, BoundaryKind::periodic), g);
  for (auto scheme : {InterpolationScheme::trilinear, InterpolationScheme::paper_lagrange2}) {
    VectorInterpolator in(s.grid, scheme);
    in.update(s.u, s.v, s.w);
    for (double y : {0.1, 0.77, 1.3}) {
      const Vec3 a = in.at({0.0, y, 0.05}), b = in.at({1.0, y, 0.05});
      EXPECT_NEAR(a.x, b.x, 1e-14);
      EXPECT_NEAR(a.y, b.y, 1e-14);
    }
  }
}

TEST(StaggeredGrid, SampleLocations) {
  const StaggeredGrid g(box(4, false, BoundaryKind::no_slip));
  const Vec3 u = g.position(Staggering::u, 1, 2, 3), v = g.position(Staggering::v, 1, 2, 3);
  const Vec3 w = g.position(Staggering::w, 1, 2, 3), c = g.position(Staggering::centre, 1, 2, 3);
  EXPECT_DOUBLE_EQ(u.x, 0.25); EXPECT_DOUBLE_EQ(u.y, 0.625); EXPECT_DOUBLE_EQ(u.z, 0.875);
  EXPECT_DOUBLE_EQ(v.x, 0.375); EXPECT_DOUBLE_EQ(v.y, 0.5); EXPECT_DOUBLE_EQ(v.z, 0.875);
  EXPECT_DOUBLE_EQ(w.x, 0.375); EXPECT_DOUBLE_EQ(w.y, 0.625); EXPECT_DOUBLE_EQ(w.z, 0.75);
  EXPECT_DOUBLE_EQ(c.x, 0.375);
  EXPECT_EQ(g.samples(Staggering::u, 0), 5);  // faces 0..4 on a walled axis
  EXPECT_EQ(g.samples(Staggering::u, 1), 8);
  const StaggeredGrid p(box(4, false, BoundaryKind::periodic));
  EXPECT_EQ(p.samples(Staggering::u, 0), 4);  // face 4 is face 0
}

}  // namespace
