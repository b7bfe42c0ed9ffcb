// Scene keys of Hertz–Mindlin contacts and rolling resistance: each bad input is refused
// with the file, the key, the value and what was expected; good input is converted to
// SI once (Young's modulus is a pressure: dyn/cm^2 = 0.1 Pa), and dt = "auto" follows
// the Hertz collision time at the stated impact speed or a Rayleigh-time fraction.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "cdm/solver/contact/hertz_mindlin.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "support.hpp"
#include "cdm/solver/simulation.hpp"

namespace {

const std::string hertz = R"(
units = "SI"

[modules]
normal_contact = "hertz_mindlin"
tangential = "spring_coulomb"

[[materials]]
name = "ball"
density = 2500.0
youngs_modulus = 7.0e10
poisson_ratio = 0.25

[[materials]]
name = "floor"
youngs_modulus = 2.1e11
poisson_ratio = 0.3

[[contacts]]
pair = ["ball", "floor"]
en = 0.8
mu = 0.3

[[walls]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "floor"

[[particles]]
material = "ball"
radius = 5.0e-3
position = [0.0, 1.0e-2, 0.0]
velocity = [0.0, -1.0, 0.0]

[integrator]
scheme = "velocity_verlet"
dt = "auto"
impact_velocity = 1.0
end_time = 1.0e-2
)";

using cdm::test::replace;

using cdm::test::expect_refused;

TEST(HertzScene, LoadsWithEffectiveModuliAndHertzTimeStep) {
  const cdm::SceneSpec s = cdm::load_scene_from_string(hertz, "good.toml");
  const cdm::PairParams& pp = s.pairs.get(0, 1);
  EXPECT_EQ(pp.law, cdm::ContactLaw::hertz_mindlin);
  EXPECT_DOUBLE_EQ(pp.e_star, 1.0 / ((1 - 0.0625) / 7.0e10 + (1 - 0.09) / 2.1e11));
  EXPECT_DOUBLE_EQ(pp.hertz_alpha, cdm::contact::hertz_alpha_exact(0.8));
  // dt = t_H(1 m/s)/50 with the wall's m* = m, R* = R.
  const double m = 2500.0 * 4.0 / 3.0 * std::numbers::pi * 1.25e-7;
  const double t_h = cdm::contact::hertz_collision_time(m, 5e-3, pp.e_star, 1.0);
  EXPECT_DOUBLE_EQ(s.t_col_min, t_h);
  EXPECT_DOUBLE_EQ(s.dt, t_h / 50.0);
  cdm::Simulation sim(s);
  EXPECT_EQ(sim.module_names().back(), "hertz_mindlin+spring_coulomb");
}

TEST(HertzScene, CgsYoungsModulusIsAPressure) {
  std::string cgs = replace(hertz, "units = \"SI\"", "units = \"cgs\"");
  cgs = replace(cgs, "density = 2500.0", "density = 2.5");
  cgs = replace(cgs, "youngs_modulus = 7.0e10", "youngs_modulus = 7.0e11");   // dyn/cm^2
  cgs = replace(cgs, "youngs_modulus = 2.1e11", "youngs_modulus = 2.1e12");
  cgs = replace(cgs, "radius = 5.0e-3", "radius = 0.5");
  cgs = replace(cgs, "position = [0.0, 1.0e-2, 0.0]", "position = [0.0, 1.0, 0.0]");
  cgs = replace(cgs, "velocity = [0.0, -1.0, 0.0]", "velocity = [0.0, -100.0, 0.0]");
  cgs = replace(cgs, "impact_velocity = 1.0", "impact_velocity = 100.0");
  const cdm::SceneSpec a = cdm::load_scene_from_string(hertz, "si.toml");
  const cdm::SceneSpec b = cdm::load_scene_from_string(cgs, "cgs.toml");
  EXPECT_NEAR(b.pairs.get(0, 1).e_star, a.pairs.get(0, 1).e_star, 1e-12 * a.pairs.get(0, 1).e_star);
  EXPECT_NEAR(b.dt, a.dt, 1e-12 * a.dt);
}

TEST(HertzScene, ElasticConstantsRequiredAndOnlyWhereUsed) {
  expect_refused(replace(hertz, "youngs_modulus = 2.1e11\npoisson_ratio = 0.3\n", ""),
                 {"materials[1].youngs_modulus", "is missing", "floor", "contacts[0] uses model hertz_mindlin"});
  expect_refused(replace(hertz, "poisson_ratio = 0.25", ""), {"materials[0].poisson_ratio", "missing"});
  expect_refused(replace(hertz, "poisson_ratio = 0.25", "poisson_ratio = 0.5"), {"materials[0].poisson_ratio", "0.5", "(-1, 0.5)"});
  expect_refused(replace(hertz, "youngs_modulus = 7.0e10", "youngs_modulus = -7.0e10"), {"materials[0].youngs_modulus", "> 0"});
  // A linear pair does not use them.
  std::string lin = replace(hertz, "normal_contact = \"hertz_mindlin\"", "normal_contact = \"linear_spring_dashpot\"");
  lin = replace(lin, "en = 0.8", "kn = 1.0e4\nen = 0.8");
  expect_refused(lin, {"materials[0].youngs_modulus", "is not used", "no [[contacts]] entry with model hertz_mindlin"});
}

TEST(HertzScene, KeysOfTheOtherLawAreRefused) {
  expect_refused(replace(hertz, "en = 0.8", "kn = 1.0e4\nen = 0.8"), {"contacts[0].kn", "not used", "hertz_mindlin"});
  expect_refused(replace(hertz, "mu = 0.3", "mu = 0.3\nkt_factor = 0.4"), {"contacts[0].kt_factor", "not used"});
  expect_refused(replace(hertz, "en = 0.8", "en = 0.8\ndamping = \"viscous\""),
                 {"contacts[0].damping", "viscous", "\"exact_restitution\" or \"tsuji\""});
  expect_refused(replace(hertz, "en = 0.8", "en = 0.8\nmodel = \"jkr\""), {"contacts[0].model", "jkr"});
  // A linear pair (named per entry) refuses the Hertz dashpot rule.
  std::string lin = replace(hertz, "en = 0.8", "model = \"linear_spring_dashpot\"\nkn = 1.0e4\nen = 0.8\ndamping = \"tsuji\"");
  expect_refused(lin, {"contacts[0].damping", "not used", "eq 29"});
  expect_refused(replace(hertz, "normal_contact = \"hertz_mindlin\"", "normal_contact = \"hertz\""),
                 {"modules.normal_contact", "\"hertz\"", "\"hertz_mindlin\""});
}

TEST(HertzScene, TimeStepNeedsAnImpactSpeedOrARayleighFraction) {
  const std::string no_v = replace(hertz, "impact_velocity = 1.0\n", "");
  expect_refused(no_v, {"integrator.dt", "integrator.impact_velocity", "integrator.rayleigh_fraction"});
  // A Rayleigh-time fraction instead.
  const cdm::SceneSpec s = cdm::load_scene_from_string(replace(no_v, "dt = \"auto\"", "dt = \"auto\"\nrayleigh_fraction = 0.2"), "good.toml");
  const double tr = cdm::contact::rayleigh_time(5e-3, 2500.0, 7.0e10, 0.25);
  EXPECT_DOUBLE_EQ(s.rayleigh_time_min, tr);
  EXPECT_DOUBLE_EQ(s.dt, 0.2 * tr);
  // An explicit step: refused above the Rayleigh time, and above t_H/10 at the impact speed.
  expect_refused(replace(no_v, "dt = \"auto\"", "dt = 1.0e-5"), {"integrator.dt", "Rayleigh time", "1e-05"});
  expect_refused(replace(hertz, "dt = \"auto\"", "dt = 4.0e-6"), {"integrator.dt", "t_col/10", "impact_velocity"});
  EXPECT_NO_THROW(cdm::load_scene_from_string(replace(hertz, "dt = \"auto\"", "dt = 1.0e-7"), "good.toml"));
  // Keys that only Hertz–Mindlin or only "auto" use.
  expect_refused(replace(hertz, "dt = \"auto\"", "dt = 1.0e-7\nrayleigh_fraction = 0.2"),
                 {"integrator.rayleigh_fraction", "not used", "not \"auto\""});
  expect_refused(replace(hertz, "impact_velocity = 1.0", "impact_velocity = 0.0"), {"integrator.impact_velocity", "> 0"});
  std::string lin = replace(hertz, "normal_contact = \"hertz_mindlin\"", "normal_contact = \"linear_spring_dashpot\"");
  lin = replace(lin, "en = 0.8", "kn = 1.0e4\nen = 0.8");
  lin = replace(lin, "youngs_modulus = 7.0e10\npoisson_ratio = 0.25\n", "");
  lin = replace(lin, "youngs_modulus = 2.1e11\npoisson_ratio = 0.3\n", "");
  expect_refused(lin, {"integrator.impact_velocity", "not used", "no [[contacts]] entry uses model hertz_mindlin"});
}

TEST(RollingScene, KeysAndModule) {
  const std::string roll = replace(replace(hertz, "tangential = \"spring_coulomb\"",
                                           "tangential = \"spring_coulomb\"\nrolling_resistance = \"constant_torque\""),
                                   "mu = 0.3", "mu = 0.3\nrolling_mu = 0.05");
  const cdm::SceneSpec s = cdm::load_scene_from_string(roll, "good.toml");
  EXPECT_DOUBLE_EQ(s.pairs.get(0, 1).rolling_mu, 0.05);
  cdm::Simulation sim(s);
  ASSERT_EQ(sim.module_names().size(), 2u);
  EXPECT_EQ(sim.module_names()[1], "rolling_resistance(constant_torque)");
  expect_refused(replace(roll, "rolling_mu = 0.05", ""), {"contacts[0].rolling_mu", "missing"});
  expect_refused(replace(roll, "rolling_mu = 0.05", "rolling_mu = -0.05"), {"contacts[0].rolling_mu", ">= 0"});
  expect_refused(replace(hertz, "mu = 0.3", "mu = 0.3\nrolling_mu = 0.05"),
                 {"contacts[0].rolling_mu", "not used", "modules.rolling_resistance is \"none\""});
  expect_refused(replace(roll, "rolling_resistance = \"constant_torque\"", "rolling_resistance = \"epsd\""),
                 {"modules.rolling_resistance", "epsd", "\"constant_torque\""});
  // Rolling resistance alone makes particles rotate (angular velocity accepted), and
  // needs a normal contact.
  std::string spin = replace(roll, "tangential = \"spring_coulomb\"\n", "");
  spin = replace(spin, "mu = 0.3\n", "");
  spin = replace(spin, "velocity = [0.0, -1.0, 0.0]", "velocity = [0.0, -1.0, 0.0]\nangular_velocity = [5.0, 0.0, 0.0]");
  cdm::Simulation spinning(cdm::load_scene_from_string(spin, "good.toml"));
  EXPECT_TRUE(spinning.particles().has_rotation());
  EXPECT_DOUBLE_EQ(spinning.particles().wx[0], 5.0);
}

}  // namespace
