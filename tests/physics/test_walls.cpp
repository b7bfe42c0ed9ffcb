// Analytic walls (walls.hpp) and their motion (walls/wall_motion.hpp): the gap and normal
// of cylinders, cones and their caps against hand-computed values; one contact at a
// convex rim; the listing distance bounding the contact gap; the motion's velocity as the
// derivative of its position; Galilean invariance of an impact on a translating wall;
// and the Verlet list's wall candidates staying complete while a wall moves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"
#include "cdm/solver/walls.hpp"

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

cdm::Wall cylinder(cdm::WallShape shape, bool inside, bool capped) {
  cdm::Wall w;
  w.shape = shape;
  w.point = {0, 0, 0};
  w.normal = {0, 0, 1};
  w.radius_start = w.radius_end = 1.0;
  w.length = 2.0;
  w.inside = inside;
  w.capped_start = w.capped_end = capped;
  return w;
}

void expect_vec(cdm::Vec3 a, cdm::Vec3 b, double tol = 1e-15) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

}  // namespace

TEST(WallGeometry, CylinderFacesInsideAndOutside) {
  const cdm::Wall in = cylinder(cdm::WallShape::lateral, true, false);
  cdm::WallGap g = in.gap({0.7, 0, 1}, 0.1);
  EXPECT_NEAR(g.gap, 0.3, 1e-15);
  expect_vec(g.normal, {-1, 0, 0});
  EXPECT_TRUE(g.face);
  // A centre slightly beyond the surface: a negative gap, the normal still inwards.
  g = in.gap({0, 1.05, 1}, 0.1);
  EXPECT_NEAR(g.gap, -0.05, 1e-15);
  expect_vec(g.normal, {0, -1, 0});
  // Far outside an inside wall: no contact.
  EXPECT_EQ(in.gap({3, 0, 1}, 0.1).gap, inf);
  const cdm::Wall out = cylinder(cdm::WallShape::lateral, false, false);
  g = out.gap({1.5, 0, 1}, 0.1);
  EXPECT_NEAR(g.gap, 0.5, 1e-15);
  expect_vec(g.normal, {1, 0, 0});
}

TEST(WallGeometry, CapsAndTheConcaveCornerAreTwoPlanes) {
  const cdm::Wall lat = cylinder(cdm::WallShape::lateral, true, true);
  const cdm::Wall c0 = cylinder(cdm::WallShape::cap_start, true, true);
  const cdm::Wall c1 = cylinder(cdm::WallShape::cap_end, true, true);
  const cdm::Vec3 X{0.95, 0, 0.05};  // in the corner of the lateral surface and the start cap
  EXPECT_NEAR(lat.gap(X, 0.1).gap, 0.05, 1e-15);
  expect_vec(lat.gap(X, 0.1).normal, {-1, 0, 0});
  EXPECT_NEAR(c0.gap(X, 0.1).gap, 0.05, 1e-15);
  expect_vec(c0.gap(X, 0.1).normal, {0, 0, 1});
  EXPECT_NEAR(c1.gap({0.2, 0.3, 1.9}, 0.1).gap, 0.1, 1e-15);
  expect_vec(c1.gap({0.2, 0.3, 1.9}, 0.1).normal, {0, 0, -1});
}

TEST(WallGeometry, ConvexRimIsOneContact) {
  // Outside a capped cylinder, beyond the start rim: the cap owns the rim, the lateral
  // surface does not see it.
  const cdm::Wall lat = cylinder(cdm::WallShape::lateral, false, true);
  const cdm::Wall c0 = cylinder(cdm::WallShape::cap_start, false, true);
  const cdm::Vec3 X{1.1, 0, -0.1};
  EXPECT_EQ(lat.gap(X, 0.2).gap, inf);
  const cdm::WallGap g = c0.gap(X, 0.2);
  EXPECT_NEAR(g.gap, std::sqrt(0.02), 1e-15);
  expect_vec(g.normal, {std::sqrt(0.5), 0, -std::sqrt(0.5)});
  EXPECT_FALSE(g.face);
  // Open at that end: the lateral surface owns its rim.
  const cdm::Wall open = cylinder(cdm::WallShape::lateral, false, false);
  EXPECT_NEAR(open.gap(X, 0.2).gap, std::sqrt(0.02), 1e-15);
  // Beside the lateral face the cap does not act.
  EXPECT_EQ(c0.gap({1.1, 0, 0.05}, 0.2).gap, inf);
}

TEST(WallGeometry, ConeFaceAgainstTheMeridianLine) {
  cdm::Wall w = cylinder(cdm::WallShape::lateral, true, false);
  w.radius_end = 0.5;  // R from 1 at s = 0 to 0.5 at s = 1... over L = 2
  // Inside, at (x, 0, s): the line through (0, 1) and (2, 0.5) in (s, ρ); distance of
  // (s, ρ) from it = ((1 - ρ) L - s (R0 - R1)) / hypot(L, R0 - R1).
  const double s = 0.8, rho = 0.3, L = 2.0;
  const cdm::WallGap g = w.gap({rho, 0, s}, 0.1);
  EXPECT_NEAR(g.gap, ((1 - rho) * L - s * 0.5) / std::hypot(L, 0.5), 1e-15);
  expect_vec(g.normal, cdm::Vec3{-L, 0, -0.5} * (1.0 / std::hypot(L, 0.5)));
}

TEST(WallGeometry, ListingDistanceBoundsTheGapAndIsLipschitz) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  for (cdm::WallShape shape : {cdm::WallShape::lateral, cdm::WallShape::cap_start, cdm::WallShape::cap_end})
    for (bool inside : {true, false})
      for (bool capped : {true, false}) {
        cdm::Wall w = cylinder(shape, inside, capped);
        w.radius_end = 0.4;
        for (int k = 0; k < 20000; ++k) {
          const cdm::Vec3 X{u(rng), u(rng), u(rng) + 1.0}, Y = X + 0.01 * cdm::Vec3{u(rng), u(rng), u(rng)};
          const double r = 0.2;
          if (w.gap(X, r).gap < r) {
            ASSERT_LT(w.reach_distance(X), r) << X.x << " " << X.y << " " << X.z;
          }
          ASSERT_LE(std::abs(w.reach_distance(X) - w.reach_distance(Y)), cdm::norm(X - Y) * (1 + 1e-12) + 1e-15);
        }
      }
}

TEST(WallMotion, VelocityIsTheDerivativeOfThePosition) {
  cdm::WallMotion tr, osc, rot;
  tr.kind = cdm::WallMotion::Kind::translation;
  tr.velocity = {0.1, -0.2, 0.3};
  osc.kind = cdm::WallMotion::Kind::oscillation;
  osc.amplitude = {0.0, 0.002, 0.001};
  osc.frequency = 7.0;
  osc.phase = 0.4;
  rot.kind = cdm::WallMotion::Kind::rotation;
  rot.origin = {0.1, 0.2, -0.3};
  rot.axis = cdm::Vec3{1, 2, 2} * (1.0 / 3.0);
  rot.angular_velocity = 2.5;
  const cdm::Vec3 x0{0.3, -0.1, 0.25};
  for (const cdm::WallMotion& m : {tr, osc, rot})
    for (double t : {0.0, 0.13, 1.7}) {
      const double h = 1e-5;
      const cdm::Vec3 fd = (1.0 / (2 * h)) * (m.point(x0, t + h) - m.point(x0, t - h));
      expect_vec(m.surface_velocity(m.point(x0, t), t), fd, 1e-8);
      // A turned direction keeps its length.
      EXPECT_NEAR(cdm::norm(m.direction({0, 0.6, 0.8}, t)), 1.0, 1e-15);
      // The displacement bound holds.
      const double reach = cdm::norm(cdm::cross(x0 - m.origin, m.axis));
      EXPECT_LE(cdm::norm(m.point(x0, t + 0.05) - m.point(x0, t)), m.shift_bound(t, t + 0.05, reach) * (1 + 1e-12));
    }
  // A drum turning about its own axis keeps its place: nothing to list again.
  cdm::Wall drum = cylinder(cdm::WallShape::lateral, true, true);
  drum.motion.kind = cdm::WallMotion::Kind::rotation;
  drum.motion.axis = {0, 0, 1};
  drum.motion.angular_velocity = 3.0;
  EXPECT_EQ(drum.shift_bound(0.0, 10.0), 0.0);
  drum.motion.origin = {0.5, 0, 0};  // off its axis: it sweeps
  EXPECT_GT(drum.shift_bound(0.0, 0.1), 0.1);
}

namespace {

// A frictional sphere (r = 1 cm) meeting a plane wall at z = 0: the wall translating at
// @p wall_velocity, the sphere launched at @p v (with spin), Hertz–Mindlin or linear.
std::string impact_scene(cdm::Vec3 v, cdm::Vec3 wall_velocity, const std::string& law) {
  auto vec = [](cdm::Vec3 a) {
    char b[200];
    std::snprintf(b, sizeof b, "[%.17g, %.17g, %.17g]", a.x, a.y, a.z);
    return std::string(b);
  };
  const std::string elastic = law == "hertz_mindlin" ? "youngs_modulus = 1.0e7\npoisson_ratio = 0.3\n" : "";
  std::string s = R"(units = "SI"
[modules]
normal_contact = ")" + law + R"("
tangential = "spring_coulomb"
[[materials]]
name = "ball"
density = 2500.0
)" + elastic + R"([[materials]]
name = "plate"
)" + elastic + R"([[contacts]]
pair = ["ball", "plate"]
en = 0.8
mu = 0.3
)" + (law == "linear_spring_dashpot" ? "kn = 1.0e4\n" : "") +
                  R"([[walls]]
name = "plate"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
material = "plate"
)";
  if (wall_velocity.x != 0.0 || wall_velocity.y != 0.0 || wall_velocity.z != 0.0)
    s += "motion = { type = \"translation\", velocity = " + vec(wall_velocity) + " }\n";
  s += R"([[particles]]
material = "ball"
radius = 0.01
position = [0.0, 0.0, 0.0102]
velocity = )" + vec(v) + R"(
angular_velocity = [0.0, 20.0, 5.0]
[integrator]
scheme = "velocity_verlet"
dt = 1.0e-6
end_time = 2.0e-3
)";
  return s;
}

}  // namespace

// An impact on a wall moving at −u is the impact at v + u on a wall at rest, seen from a
// frame moving at −u: positions differ by −u t, velocities by −u, spins not at all, to
// round-off, through approach, contact (normal and tangential) and rebound.
TEST(MovingWalls, GalileanInvariance) {
  const cdm::Vec3 v{0.2, -0.1, -0.3}, u{0.15, 0.05, -0.4};
  for (const std::string law : {"linear_spring_dashpot", "hertz_mindlin"}) {
    cdm::Simulation a(cdm::load_scene_from_string(impact_scene(v, -1.0 * u, law), "moving.toml"));
    cdm::Simulation b(cdm::load_scene_from_string(impact_scene(v + u, {}, law), "rest.toml"));
    ASSERT_EQ(a.total_steps(), b.total_steps());
    double max_dx = 0, max_dv = 0, max_dw = 0, min_z = 1.0;
    for (std::uint64_t k = 0; k < a.total_steps(); ++k) {
      a.step();
      b.step();
      const cdm::ParticleStore &pa = a.particles(), &pb = b.particles();
      const double t = a.time();
      max_dx = std::max(max_dx, cdm::norm(pa.position(0) + t * u - pb.position(0)));
      max_dv = std::max(max_dv, cdm::norm(pa.velocity(0) + u - pb.velocity(0)));
      max_dw = std::max(max_dw, cdm::norm(pa.angular_velocity(0) - pb.angular_velocity(0)));
      min_z = std::min(min_z, pb.z[0]);
    }
    EXPECT_LT(min_z, 0.01) << law << ": the sphere never touched the wall";
    EXPECT_GT(b.particles().vz[0], 0.0) << law << ": no rebound";
    // Round-off: positions near 1e-2 m carry ~1e-18 m per step over 2000 steps; the
    // velocities ~1e-16 m/s per step.
    std::printf("%s: max |dx| %.3g m, |dv| %.3g m/s, |dw| %.3g rad/s\n", law.c_str(), max_dx, max_dv, max_dw);
    EXPECT_LT(max_dx, 1e-13) << law;
    EXPECT_LT(max_dv, 1e-11) << law;
    EXPECT_LT(max_dw, 1e-9) << law;  // spins near 20 rad/s
  }
}

// Particles at rest and a wall sweeping through them: the forces with a Verlet skin (the
// wall listed again as it moves) equal those with no skin (everything listed every
// evaluation), at every evaluation, for a translating, an oscillating and a rotating wall.
TEST(MovingWalls, WallCandidatesStayCompleteAsTheWallMoves) {
  cdm::ParticleStore p;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 400; ++i)
    p.add({0.2 * u(rng) - 0.1, 0.2 * u(rng) - 0.1, 0.05 * u(rng)}, {}, 1e-3, 1.0, 0);
  cdm::PairTable pairs(2);
  cdm::PairParams pp;
  pp.kn = 1e3;
  pp.en = 0.9;
  pairs.set(0, 1, pp);
  pairs.set(0, 0, pp);
  std::vector<cdm::WallMotion> motions(3);
  motions[0].kind = cdm::WallMotion::Kind::translation;
  motions[0].velocity = {0, 0, 1.0};
  motions[1].kind = cdm::WallMotion::Kind::oscillation;
  motions[1].amplitude = {0, 0, 0.03};
  motions[1].frequency = 20.0;
  motions[2].kind = cdm::WallMotion::Kind::rotation;
  motions[2].axis = {1, 0, 0};
  motions[2].angular_velocity = 10.0;
  for (const cdm::WallMotion& m : motions) {
    cdm::Wall w;
    w.name = "plate";
    w.point = {0, 0, -0.002};
    w.normal = {0, 0, 1};
    w.material = 1;
    w.motion = m;
    cdm::ContactModule listed(pairs, {w}, false, 0.2e-3), every(pairs, {w}, false, 0.0);
    std::size_t touching = 0;
    for (int k = 0; k < 400; ++k) {
      const double t = 1e-4 * k;
      cdm::ParticleStore a = p, b = p;
      listed.set_time(t);
      every.set_time(t);
      a.clear_forces();
      b.clear_forces();
      listed.add_forces(a, 1e-5);
      every.add_forces(b, 1e-5);
      for (std::size_t i = 0; i < p.size(); ++i) {
        ASSERT_EQ(a.fz[i], b.fz[i]) << "motion " << static_cast<int>(m.kind) << " t " << t << " particle " << i;
        touching += a.fz[i] != 0.0;
      }
    }
    EXPECT_GT(touching, 1000u) << static_cast<int>(m.kind);
  }
}

// Solid-body rotation: a ball riding the inside of a drum turning at Ω, moving and
// spinning with it (v = Ω × x, ω = Ω), has no slip at its contact, so friction leaves it
// alone and it goes round with the drum — if the drum's surface velocity enters the
// contact. Standing still, the same drum would brake the ball (its contact point slides
// at Ω (ρ + r)).
TEST(MovingWalls, BallRidesATurningDrumAsASolidBody) {
  const double R = 0.05, r = 0.005, omega = 2.0;
  const double rho0 = R - r;
  char text[4000];
  auto scene = [&](double drum_omega) {
    std::snprintf(text, sizeof text, R"(units = "SI"
[modules]
normal_contact = "linear_spring_dashpot"
tangential = "spring_coulomb"
[[materials]]
name = "ball"
density = 2500.0
[[materials]]
name = "drum"
[[contacts]]
pair = ["ball", "drum"]
kn = 1.0e4
en = 0.5
mu = 0.5
[[walls]]
name = "drum"
type = "cylinder"
point = [0.0, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]
length = 0.02
radius = %.17g
caps = "both"
material = "drum"
motion = { type = "rotation", origin = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], angular_velocity = %.17g }
[[particles]]
material = "ball"
radius = %.17g
position = [%.17g, 0.0, 0.01]
velocity = [0.0, %.17g, 0.0]
angular_velocity = [0.0, 0.0, %.17g]
[integrator]
scheme = "velocity_verlet"
dt = "auto"
end_time = %.17g
[checks]
allow_initial_overlap = true   # it starts touching the wall, at R - r to round-off
)", R, drum_omega, r, rho0, omega * rho0, omega, 2.0 * M_PI / omega);
    return std::string(text);
  };
  cdm::Simulation turning(cdm::load_scene_from_string(scene(omega), "turning.toml"));
  turning.run();
  const cdm::ParticleStore& p = turning.particles();
  const double t = turning.time();
  const double rho = std::hypot(p.x[0], p.y[0]);
  const double lag = std::remainder(omega * t - std::atan2(p.y[0], p.x[0]), 2.0 * M_PI);
  std::printf("after one turn: radius %.9g m (R - r = %.9g), lag %.3g rad, spin %.9g rad/s\n", rho, rho0, lag,
              p.wz[0]);
  // The ball settles onto the wall by the centripetal overlap m Ω² ρ / kn = 2.4e-8 m after
  // the first contact's few-collision-time transient (it starts tangent, flying straight):
  // radius within 1e-6 m, position within 1e-4 rad of the drum's turn, spin within 1e-4.
  // Measured: overlap 2.36e-8 m, lag 4.7e-6 rad, spin 2.0000134 rad/s.
  EXPECT_NEAR(rho, rho0, 1e-6);
  EXPECT_LT(std::abs(lag), 1e-4);
  EXPECT_NEAR(p.wz[0], omega, 1e-4 * omega);
  // A drum at rest brakes the same ball: the test can tell the difference.
  cdm::Simulation still(cdm::load_scene_from_string(scene(0.0), "still.toml"));
  still.run();
  EXPECT_GT(std::abs(still.particles().wz[0] - omega), 0.1 * omega);
}
