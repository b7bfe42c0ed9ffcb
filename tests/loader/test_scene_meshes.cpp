// [[meshes]]: STL files read (ASCII and binary), placed by scale, rotation and offset, and
// bad meshes refused with a SceneError naming the scene key, the STL file and the
// triangle (counted from 1) -- `cdm run` exits 2 on it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "cdm/solver/scene_loader.hpp"
#include "scene_text.hpp"

namespace fs = std::filesystem;

namespace {

const std::string base = cdm_test::scene_head({.grain = "ball", .kn = 1.0e4, .en = 0.9, .grain_pairs = false}) + R"(
[[particles]]
material = "ball"
radius = 0.01
position = [0.1, 0.2, 0.5]

[integrator]
scheme = "velocity_verlet"
dt = "auto"
end_time = 0.1
)";

const std::string square_ascii = R"(solid square
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 1 1 0
 endloop
endfacet
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 1 0
  vertex 0 1 0
 endloop
endfacet
endsolid square
)";

std::string binary_stl(const std::vector<std::array<float, 9>>& tris, std::uint32_t count) {
  std::string b(80, ' ');
  b.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : tris) {
    float rec[12] = {0, 0, 1};
    std::memcpy(rec + 3, t.data(), sizeof(float) * 9);
    b.append(reinterpret_cast<const char*>(rec), sizeof rec);
    b.append(2, '\0');
  }
  return b;
}

class Meshes : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("cdm_meshes_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& bytes) const {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
  }
  /// The base scene plus @p extra, written beside the STL files and loaded from there.
  cdm::SceneSpec load(const std::string& extra) const {
    write("scene.toml", base + extra);
    return cdm::load_scene((dir_ / "scene.toml").string());
  }
  /// The SceneError's message (empty if the scene loads).
  std::string error(const std::string& extra) const {
    try {
      load(extra);
    } catch (const cdm::SceneError& e) {
      return e.what();
    }
    return "";
  }
  static std::string mesh(const std::string& file, const std::string& more = "") {
    return "\n[[meshes]]\nname = \"box\"\nfile = \"" + file + "\"\nmaterial = \"steel\"\n" + more;
  }
  fs::path dir_;
};

TEST_F(Meshes, AsciiSquareLoadsWelded) {
  write("square.stl", square_ascii);
  const cdm::SceneSpec s = load(mesh("square.stl"));
  ASSERT_EQ(s.meshes.size(), 1u);
  const cdm::TriangleMesh& m = s.meshes[0];
  EXPECT_EQ(m.name, "box");
  EXPECT_EQ(m.size(), 2u);
  EXPECT_EQ(m.vertices.size(), 4u);  // the diagonal's two ends shared
  EXPECT_EQ(m.edge_count, 5u);       // four sides and the shared diagonal
  EXPECT_EQ(m.edges[0][2], m.edges[1][0]);
  EXPECT_EQ(m.normals[0].z, 1.0);
}

TEST_F(Meshes, BinaryMatchesAscii) {
  write("square.stl", binary_stl({{0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, 0}}, 2));
  const cdm::SceneSpec s = load(mesh("square.stl"));
  ASSERT_EQ(s.meshes[0].size(), 2u);
  EXPECT_EQ(s.meshes[0].vertices.size(), 4u);
  EXPECT_EQ(s.meshes[0].vertex(1, 2).y, 1.0);
}

TEST_F(Meshes, ScaleRotationOffsetInThatOrder) {
  write("square.stl", square_ascii);
  // (1, 0, 0) scaled by 2, rotated 90 degrees about z to (0, 2, 0), then offset.
  const cdm::SceneSpec s =
      load(mesh("square.stl", "scale = 2.0\nrotation = [0.0, 0.0, 90.0]\noffset = [1.0, 1.0, 3.0]\n"));
  const cdm::Vec3 v = s.meshes[0].vertex(0, 1);
  EXPECT_NEAR(v.x, 1.0, 1e-15);
  EXPECT_NEAR(v.y, 3.0, 1e-15);
  EXPECT_NEAR(v.z, 3.0, 1e-15);
}

TEST_F(Meshes, MissingFile) {
  const std::string e = error(mesh("nowhere.stl"));
  EXPECT_NE(e.find("meshes[0].file"), std::string::npos) << e;
  EXPECT_NE(e.find("nowhere.stl"), std::string::npos) << e;
}

TEST_F(Meshes, NotStlText) {
  write("notes.stl", "these are not triangles\n");
  const std::string e = error(mesh("notes.stl"));
  EXPECT_NE(e.find("notes.stl"), std::string::npos) << e;
  EXPECT_NE(e.find("is not an STL file"), std::string::npos) << e;
}

TEST_F(Meshes, NotStlBinaryCountMismatch) {
  std::string junk(300, 'x');
  write("junk.stl", junk);
  const std::string e = error(mesh("junk.stl"));
  EXPECT_NE(e.find("is not an STL file"), std::string::npos) << e;
  EXPECT_NE(e.find("300"), std::string::npos) << e;  // the file's size
}

TEST_F(Meshes, TruncatedBinary) {
  std::string b = binary_stl({{0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, 0}}, 3);  // says 3, holds 2
  write("short.stl", b);
  const std::string e = error(mesh("short.stl"));
  EXPECT_NE(e.find("counts 3 triangles"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
}

TEST_F(Meshes, TruncatedAscii) {
  write("cut.stl", square_ascii.substr(0, square_ascii.find("vertex 1 1 0\n  vertex 0 1 0")));
  const std::string e = error(mesh("cut.stl"));
  EXPECT_NE(e.find("cut.stl"), std::string::npos) << e;
  EXPECT_NE(e.find("triangle 2"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
}

TEST_F(Meshes, MissingEndsolid) {
  write("open.stl", square_ascii.substr(0, square_ascii.find("endsolid")));
  const std::string e = error(mesh("open.stl"));
  EXPECT_NE(e.find("'endsolid'"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
}

TEST_F(Meshes, NanVertexAscii) {
  std::string s = square_ascii;
  s.replace(s.find("vertex 0 1 0"), 12, "vertex 0 nan 0");
  write("nan.stl", s);
  const std::string e = error(mesh("nan.stl"));
  EXPECT_NE(e.find("nan.stl: triangle 2"), std::string::npos) << e;
  EXPECT_NE(e.find("non-finite"), std::string::npos) << e;
}

TEST_F(Meshes, InfVertexBinary) {
  const float inf = std::numeric_limits<float>::infinity();
  write("inf.stl", binary_stl({{0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, inf}}, 2));
  const std::string e = error(mesh("inf.stl"));
  EXPECT_NE(e.find("inf.stl: triangle 2"), std::string::npos) << e;
  EXPECT_NE(e.find("non-finite"), std::string::npos) << e;
}

TEST_F(Meshes, ZeroAreaTriangle) {
  std::string s = square_ascii;
  s.replace(s.find("vertex 0 1 0"), 12, "vertex 2 2 0");  // on the line through (0,0) and (1,1)
  write("flat.stl", s);
  const std::string e = error(mesh("flat.stl"));
  EXPECT_NE(e.find("flat.stl: triangle 2"), std::string::npos) << e;
  EXPECT_NE(e.find("zero area"), std::string::npos) << e;
}

TEST_F(Meshes, RepeatedCornerIsZeroArea) {
  write("dup.stl", binary_stl({{0, 0, 0, 1, 0, 0, 1, 0, 0}}, 1));
  const std::string e = error(mesh("dup.stl"));
  EXPECT_NE(e.find("dup.stl: triangle 1"), std::string::npos) << e;
  EXPECT_NE(e.find("zero area"), std::string::npos) << e;
}

TEST_F(Meshes, BadWordInAscii) {
  std::string s = square_ascii;
  s.replace(s.find("outer loop"), 10, "outer lop");
  write("typo.stl", s);
  const std::string e = error(mesh("typo.stl"));
  EXPECT_NE(e.find("line 3, in triangle 1: expected 'loop', found 'lop'"), std::string::npos) << e;
}

TEST_F(Meshes, EmptySolid) {
  write("empty.stl", "solid nothing\nendsolid nothing\n");
  const std::string e = error(mesh("empty.stl"));
  EXPECT_NE(e.find("no triangles"), std::string::npos) << e;
}

TEST_F(Meshes, BadPlacementKeys) {
  write("square.stl", square_ascii);
  EXPECT_NE(error(mesh("square.stl", "scale = 0.0\n")).find("meshes[0].scale"), std::string::npos);
  EXPECT_NE(error(mesh("square.stl", "rotation = [0.0, 400.0, 0.0]\n")).find("meshes[0].rotation"), std::string::npos);
  EXPECT_NE(error(mesh("square.stl", "offset = [0.0, 1.0]\n")).find("meshes[0].offset"), std::string::npos);
  EXPECT_NE(error(mesh("square.stl", "colour = \"red\"\n")).find("meshes[0].colour"), std::string::npos);
  std::string no_material = mesh("square.stl");
  no_material.replace(no_material.find("material = \"steel\"\n"), 19, "");
  EXPECT_NE(error(no_material).find("meshes[0].material"), std::string::npos);
  EXPECT_NE(error("\n[[meshes]]\nmaterial = \"steel\"\n").find("meshes[0].file"), std::string::npos);
}

TEST_F(Meshes, RefusedWithoutContacts) {
  write("square.stl", square_ascii);
  std::string scene = base + mesh("square.stl");
  scene.replace(scene.find("normal_contact = \"linear_spring_dashpot\""), 40, "normal_contact = \"none\"");
  write("scene.toml", scene);
  try {
    cdm::load_scene((dir_ / "scene.toml").string());
    FAIL() << "a mesh without contacts must be refused";
  } catch (const cdm::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("normal_contact"), std::string::npos) << e.what();
  }
}

TEST_F(Meshes, ParticleAcrossMeshRefused) {
  write("square.stl", square_ascii);
  // The particle at (0.1, 0.2, 0.5) with radius 0.01 touches the square lifted to z = 0.495.
  const std::string e = error(mesh("square.stl", "offset = [0.0, 0.0, 0.495]\n"));
  EXPECT_NE(e.find("lies across mesh 'box'"), std::string::npos) << e;
  EXPECT_EQ(error(mesh("square.stl", "offset = [0.0, 0.0, 0.48]\n")), "");
}

}  // namespace

TEST_F(Meshes, RandomParticlesPlacedClearOfTheMesh) {
  // The unit square at z = 0 crosses the middle of the block's box: every sphere placed
  // must keep its radius from it (above the face, |z| is the distance to the mesh).
  write("square.stl", square_ascii);
  const double r = 0.02;
  const cdm::SceneSpec s = load(mesh("square.stl") + R"(
[[contacts]]
pair = ["ball", "ball"]
kn = 1.0e4
en = 0.9

[[random_particles]]
material = "ball"
radius = 0.02
lower = [0.1, 0.1, -0.05]
upper = [0.9, 0.9, 0.05]
count = 300
seed = 3
)");
  ASSERT_EQ(s.particles.size(), 301u);
  for (std::size_t i = 1; i < s.particles.size(); ++i)
    EXPECT_GE(std::abs(s.particles[i].position.z), r) << "particle " << i;
}
