// An isolated impact never leaves faster than it arrived: a sphere thrown at 1 m/s
// against a wall (no gravity, so its speed after the contact is its exit speed), for en
// from 1e-8 to 1, both integrators, linear spring–dashpot and Hertz–Mindlin, at the dt
// that dt = "auto" gives and at the largest explicit dt the loader accepts (the one
// dt = "auto" gives with dt_divisor = 10); a dt 1 % above that is refused. The strong
// dashpot of a small en is unstable long before t_col/10 (contact/dashpot_limit.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"

namespace {

constexpr double v_in = 1.0;  // [m/s]

// dt is a TOML value: "\"auto\"" or a number; @p divisor is dt_divisor beside "auto" (0: none).
std::string scene(bool hertz, double en, const char* scheme, const std::string& dt, double divisor) {
  std::ostringstream s;
  s.precision(17);
  s << "units = \"SI\"\n[modules]\nnormal_contact = \"" << (hertz ? "hertz_mindlin" : "linear_spring_dashpot")
    << "\"\n[[materials]]\nname = \"ball\"\ndensity = 2500.0\n";
  if (hertz) s << "youngs_modulus = 1.0e8\npoisson_ratio = 0.3\n";
  s << "[[materials]]\nname = \"floor\"\n";
  if (hertz) s << "youngs_modulus = 1.0e8\npoisson_ratio = 0.3\n";
  s << "[[contacts]]\npair = [\"ball\", \"floor\"]\nen = " << en << "\n";
  if (!hertz) s << "kn = 1.0e4\n";
  s << "[[walls]]\nname = \"floor\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nmaterial = \"floor\"\n"
    << "[[particles]]\nmaterial = \"ball\"\nradius = 0.01\nposition = [0.0, 0.011, 0.0]\n"
    << "velocity = [0.0, " << -v_in << ", 0.0]\n"
    << "[integrator]\nscheme = \"" << scheme << "\"\ndt = " << dt << "\nend_time = 0.1\n";
  if (divisor > 0.0) s << "dt_divisor = " << divisor << "\n";
  if (hertz) s << "impact_velocity = " << v_in << "\n";
  s << "[output]\ninterval = 0.01\n";
  return s.str();
}

// The ball's speed at the end: the exit speed if it left, its speed in the contact if not.
double exit_speed(const std::string& text) {
  cdm::Simulation sim(cdm::load_scene_from_string(text, "impact.toml"));
  sim.run();
  const auto& p = sim.particles();
  return std::sqrt(p.vx[0] * p.vx[0] + p.vy[0] * p.vy[0] + p.vz[0] * p.vz[0]);
}

std::string number(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

TEST(Stability, ImpactNeverLeavesFasterThanItArrived) {
  for (bool hertz : {false, true})
    for (const char* scheme : {"paper_euler", "velocity_verlet"})
      for (double en : {1e-8, 1e-6, 1e-4, 1e-2, 0.3, 0.9, 1.0}) {
        const std::string what =
            std::string(hertz ? "hertz_mindlin " : "linear ") + scheme + " en = " + number(en);
        // The largest explicit dt the loader accepts: min(t_col/10, the dashpot's limit).
        const double dt_max = cdm::load_scene_from_string(scene(hertz, en, scheme, "\"auto\"", 10.0), "impact.toml").dt;
        for (const std::string& dt : {std::string("\"auto\""), number(dt_max)}) {
          const double e = exit_speed(scene(hertz, en, scheme, dt, 0.0)) / v_in;
          // At most the model's en plus the schemes' error at t_col/10 (below 0.05,
          // test_dashpot_limit.cpp), and below 1 whenever the contact dissipates.
          EXPECT_LE(e, en + 0.05) << what << " dt = " << dt;
          if (en < 1.0) {
            EXPECT_LT(e, 1.0) << what << " dt = " << dt;
          }
        }
        EXPECT_THROW(cdm::load_scene_from_string(scene(hertz, en, scheme, number(1.01 * dt_max), 0.0), "impact.toml"),
                     cdm::SceneError)
            << what;
      }
}

// The message for a dt above the dashpot's limit names the key, the limit and the pair.
TEST(Stability, DtAboveTheDashpotLimitIsRefusedWithTheLimit) {
  const double dt_max =
      cdm::load_scene_from_string(scene(false, 1e-4, "paper_euler", "\"auto\"", 10.0), "impact.toml").dt;
  try {
    cdm::load_scene_from_string(scene(false, 1e-4, "paper_euler", number(1.01 * dt_max), 0.0), "impact.toml");
    FAIL() << "dt above the dashpot limit accepted";
  } catch (const cdm::SceneError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("integrator.dt"), std::string::npos) << m;
    EXPECT_NE(m.find("dashpot"), std::string::npos) << m;
    EXPECT_NE(m.find("ball-wall 'floor'"), std::string::npos) << m;
    EXPECT_NE(m.find("paper_euler"), std::string::npos) << m;
  }
}

}  // namespace
