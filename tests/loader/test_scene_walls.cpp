// [[walls]] beyond planes: cylinders, cones and their motion. Each bad value is refused
// with a SceneError naming the key, the value and what was expected; good ones load into
// the surfaces the contact loop sees.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "cdm/solver/scene_loader.hpp"
#include "scene_text.hpp"

namespace {

// A ball in a drum of radius 0.05 m along y, and @p wall_extra appended to the wall.
std::string drum(const std::string& wall_extra, const std::string& type_keys = "type = \"cylinder\"\nradius = 0.05\n") {
  return cdm_test::scene_head({.grain = "ball", .kn = 1.0e3, .en = 0.9, .grain_pairs = false}) + R"(
[[particles]]
material = "ball"
radius = 0.002
position = [0.0, 0.01, 0.0]
[integrator]
scheme = "velocity_verlet"
dt = "auto"
end_time = 0.01
[[walls]]
name = "drum"
point = [0.0, 0.0, 0.0]
axis = [0.0, 1.0, 0.0]
length = 0.02
material = "steel"
)" + type_keys + wall_extra;
}

cdm::SceneSpec load(const std::string& text) { return cdm::load_scene_from_string(text, "drum.toml"); }

void expect_refused(const std::string& text, const std::vector<std::string>& fragments) {
  try {
    load(text);
    FAIL() << "accepted; expected an error with '" << fragments.front() << "'";
  } catch (const cdm::SceneError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("drum.toml"), std::string::npos) << msg;
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "message lacks '" << f << "': " << msg;
  }
}

}  // namespace

TEST(SceneWalls, CappedCylinderLoadsAsItsThreeSurfaces) {
  const cdm::SceneSpec s = load(drum("caps = \"both\"\n"));
  ASSERT_EQ(s.walls.size(), 3u);
  EXPECT_EQ(s.walls[0].shape, cdm::WallShape::lateral);
  EXPECT_EQ(s.walls[1].shape, cdm::WallShape::cap_start);
  EXPECT_EQ(s.walls[2].shape, cdm::WallShape::cap_end);
  EXPECT_EQ(s.walls[1].name, "drum.start_cap");
  EXPECT_EQ(s.walls[0].radius_start, 0.05);
  EXPECT_EQ(s.walls[0].radius_end, 0.05);
  EXPECT_TRUE(s.walls[0].inside);
  EXPECT_EQ(s.walls[0].normal.y, 1.0);
  EXPECT_FALSE(s.walls[0].motion.moving());
}

TEST(SceneWalls, RotationAndConeLoad) {
  std::string t = drum("motion = { type = \"rotation\", origin = [0, 0, 0], axis = [0, 2, 0], angular_velocity = 3.0 }\n",
                       "type = \"cone\"\nradius_start = 0.05\nradius_end = 0.0\nside = \"outside\"\n");
  t.replace(t.find("position = [0.0, 0.01, 0.0]"), 27, "position = [0.08, 0.01, 0.0]");  // outside the cone
  const cdm::SceneSpec s = load(t);
  ASSERT_EQ(s.walls.size(), 1u);
  EXPECT_FALSE(s.walls[0].inside);
  EXPECT_EQ(s.walls[0].motion.kind, cdm::WallMotion::Kind::rotation);
  EXPECT_EQ(s.walls[0].motion.axis.y, 1.0);
  EXPECT_EQ(s.walls[0].motion.angular_velocity, 3.0);
}

TEST(SceneWalls, CgsLengthsAndVelocitiesAreConverted) {
  std::string text = drum("motion = { type = \"translation\", velocity = [0, 0, 10.0] }\n");
  // The whole scene in cgs: lengths ×0.01 m/cm, the density ×1000 (kg/m³)/(g/cm³), the
  // stiffness ×0.001 (N/m)/(dyn/cm), g in cm/s².
  text.replace(text.find("units = \"SI\""), 12, "units = \"cgs\"");
  text.replace(text.find("g = [0.0, 0.0, -9.81]"), 21, "g = [0.0, 0.0, -981.0]");
  text.replace(text.find("density = 2500.0"), 16, "density = 2.5");
  text.replace(text.find("kn = 1000.0"), 11, "kn = 1.0e6");
  text.replace(text.find("radius = 0.002"), 14, "radius = 0.2");
  text.replace(text.find("position = [0.0, 0.01, 0.0]"), 27, "position = [0.0, 1.0, 0.0]");
  text.replace(text.find("length = 0.02"), 13, "length = 2.0");
  text.replace(text.find("radius = 0.05"), 13, "radius = 5.0");
  const cdm::SceneSpec s = load(text);
  EXPECT_DOUBLE_EQ(s.walls[0].motion.velocity.z, 0.1);
  EXPECT_DOUBLE_EQ(s.walls[0].length, 0.02);
  EXPECT_DOUBLE_EQ(s.walls[0].radius_start, 0.05);
}

TEST(SceneWalls, ZeroOrNegativeSizesAreRefused) {
  expect_refused(drum("", "type = \"cylinder\"\nradius = 0.0\n"), {"walls[0].radius", "> 0"});
  expect_refused(drum("", "type = \"cylinder\"\nradius = -1.0\n"), {"walls[0].radius", "> 0"});
  expect_refused(drum("", "type = \"cylinder\"\n"), {"walls[0].radius", "missing"});
  std::string neg = drum("");
  neg.replace(neg.find("length = 0.02"), 13, "length = -0.02");
  expect_refused(neg, {"walls[0].length", "-0.02", "> 0"});
}

TEST(SceneWalls, ZeroAxisIsRefused) {
  std::string z = drum("");
  z.replace(z.find("axis = [0.0, 1.0, 0.0]"), 22, "axis = [0.0, 0.0, 0.0]");
  expect_refused(z, {"walls[0].axis", "non-zero vector"});
  expect_refused(drum("motion = { type = \"rotation\", origin = [0, 0, 0], axis = [0, 0, 0], angular_velocity = 1.0 }\n"),
                 {"walls[0].motion.axis", "non-zero vector"});
}

TEST(SceneWalls, ConeWithEqualRadiiIsRefusedAsACylinder) {
  expect_refused(drum("", "type = \"cone\"\nradius_start = 0.05\nradius_end = 0.05\n"),
                 {"walls[0].radius_end", "type = \"cylinder\""});
  expect_refused(drum("", "type = \"cone\"\nradius_start = -0.05\nradius_end = 0.05\n"), {"walls[0].radius_start", ">= 0"});
  expect_refused(drum("caps = \"start\"\n", "type = \"cone\"\nradius_start = 0.0\nradius_end = 0.05\n"),
                 {"walls[0].caps", "apex"});
}

TEST(SceneWalls, UnknownTypesAndKeysAreRefused) {
  expect_refused(drum("", "type = \"sphere\"\nradius = 0.05\n"), {"walls[0].type", "\"sphere\"", "\"plane\", \"cylinder\" or \"cone\""});
  expect_refused(drum("motion = { type = \"wobble\" }\n"),
                 {"walls[0].motion.type", "\"wobble\"", "\"translation\", \"oscillation\" or \"rotation\""});
  expect_refused(drum("motion = { velocity = [0, 0, 1] }\n"), {"walls[0].motion.type", "missing"});
  expect_refused(drum("motion = { type = \"translation\", velocity = [0, 0, 1], frequency = 2.0 }\n"),
                 {"walls[0].motion.frequency", "\"translation\""});
  expect_refused(drum("motion = { type = \"translation\", speed = 1.0 }\n"), {"walls[0].motion", "speed"});
  expect_refused(drum("normal = [0, 0, 1]\n"), {"walls[0].normal", "\"cylinder\""});
  expect_refused(drum("radius_start = 0.01\n"), {"walls[0].radius_start", "\"cylinder\""});
  expect_refused(drum("caps = \"top\"\n"), {"walls[0].caps", "\"none\", \"start\", \"end\" or \"both\""});
  expect_refused(drum("side = \"in\"\n"), {"walls[0].side", "\"inside\" or \"outside\""});
  expect_refused(drum("motion = 3\n"), {"walls[0].motion", "a table"});
}

TEST(SceneWalls, OscillationNeedsAmplitudeAndFrequency) {
  expect_refused(drum("motion = { type = \"oscillation\", amplitude = [0, 0, 0], frequency = 5.0 }\n"),
                 {"walls[0].motion.amplitude", "non-zero"});
  expect_refused(drum("motion = { type = \"oscillation\", amplitude = [0, 0, 0.001], frequency = 0.0 }\n"),
                 {"walls[0].motion.frequency", "> 0"});
  expect_refused(drum("motion = { type = \"oscillation\", amplitude = [0, 0, 0.001] }\n"),
                 {"walls[0].motion.frequency", "missing"});
}

TEST(SceneWalls, ParticleOutsideTheDrumIsRefused) {
  std::string t = drum("caps = \"both\"\n");
  t.replace(t.find("position = [0.0, 0.01, 0.0]"), 27, "position = [0.08, 0.01, 0.0]");
  expect_refused(t, {"particles[0].position", "outside", "wall 'drum'"});
  std::string across = drum("caps = \"both\"\n");
  across.replace(across.find("position = [0.0, 0.01, 0.0]"), 27, "position = [0.0, 0.001, 0.0]");
  expect_refused(across, {"particles[0].position", "across", "drum.start_cap"});
}

TEST(SceneWalls, PlaneWallTakesNoCylinderKeys) {
  std::string t = drum("");
  t.replace(t.find("axis = [0.0, 1.0, 0.0]"), 22, "normal = [0.0, 1.0, 0.0]");
  t.replace(t.find("type = \"cylinder\""), 17, "type = \"plane\"");
  expect_refused(t, {"walls[0].length", "\"plane\""});
}
