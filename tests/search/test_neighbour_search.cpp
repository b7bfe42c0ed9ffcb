// The O(N) cell-list search finds exactly the contacts of the O(N^2) all-pairs
// reference: >= 10,000 random polydisperse particles, some touching walls.
#include <gtest/gtest.h>

#include <random>

#include "cdm/solver/modules.hpp"
#include "cdm/solver/neighbour_search.hpp"

namespace {

cdm::ParticleStore random_packing(std::size_t n, std::uint64_t seed, double box, double rmin, double rmax) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  cdm::ParticleStore p;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = rmin + (rmax - rmin) * u(rng);
    p.add({box * u(rng), box * u(rng), box * u(rng)}, {}, r, 2500.0, static_cast<int>(i % 2));
  }
  return p;
}

void expect_same(const std::vector<cdm::ContactPair>& a, const std::vector<cdm::ContactPair>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].i, b[k].i) << k;
    ASSERT_EQ(a[k].j, b[k].j) << k;
    ASSERT_EQ(a[k].overlap, b[k].overlap) << k;  // bit for bit: the same arithmetic
  }
}

TEST(NeighbourSearch, CellListEqualsAllPairsOnRandomPolydisperseParticles) {
  // 12,000 particles, radii spread 4x, dense enough for thousands of contacts.
  cdm::ParticleStore p = random_packing(12000, 42, 0.05, 0.5e-3, 2e-3);
  std::vector<cdm::ContactPair> cells, brute;
  cdm::CellListSearch cl;
  cdm::AllPairsSearch ap;
  for (double margin : {0.0, 0.3e-3}) {
    cl.find_contacts(p, margin, cells);
    ap.find_contacts(p, margin, brute);
    EXPECT_GT(brute.size(), 2000u) << "the test packing should be dense";
    expect_same(cells, brute);
  }
}

TEST(NeighbourSearch, DegenerateLayouts) {
  cdm::CellListSearch cl;
  cdm::AllPairsSearch ap;
  std::vector<cdm::ContactPair> a, b;
  // A long thin line of touching particles (the grid grows its cells when sparse).
  cdm::ParticleStore line;
  for (int i = 0; i < 3000; ++i) line.add({i * 1.9e-3, 0.0, 0.0}, {}, 1e-3, 2500.0, 0);
  cl.find_contacts(line, 0.0, a);
  ap.find_contacts(line, 0.0, b);
  EXPECT_EQ(b.size(), 2999u);
  expect_same(a, b);
  // Everything in one spot, and two far-apart clusters.
  cdm::ParticleStore clump;
  for (int i = 0; i < 200; ++i) clump.add({1e-6 * (i % 3), 0.0, 1e-6 * (i % 5)}, {}, 1e-3, 2500.0, 0);
  for (int i = 0; i < 200; ++i) clump.add({1e3 + 1e-4 * i, 0.0, 0.0}, {}, 1e-3, 2500.0, 0);
  cl.find_contacts(clump, 0.0, a);
  ap.find_contacts(clump, 0.0, b);
  expect_same(a, b);
}

TEST(NeighbourSearch, WallContactsMatchBruteForce) {
  // Particles inside a unit-ish box, some pushed against each of six walls.
  cdm::ParticleStore p = random_packing(10000, 7, 0.05, 0.5e-3, 2e-3);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < p.size(); i += 10) {  // every 10th touches a wall
    const double r = p.radius[i], pen = 0.5 * r * u(rng);
    switch ((i / 10) % 6) {
      case 0: p.x[i] = r - pen; break;
      case 1: p.x[i] = 0.05 - r + pen; break;
      case 2: p.y[i] = r - pen; break;
      case 3: p.y[i] = 0.05 - r + pen; break;
      case 4: p.z[i] = r - pen; break;
      default: p.z[i] = 0.05 - r + pen; break;
    }
  }
  std::vector<cdm::PlaneWall> walls = {
      {"x0", {0, 0, 0}, {1, 0, 0}, 2},    {"x1", {0.05, 0, 0}, {-1, 0, 0}, 2}, {"y0", {0, 0, 0}, {0, 1, 0}, 2},
      {"y1", {0, 0.05, 0}, {0, -1, 0}, 2}, {"z0", {0, 0, 0}, {0, 0, 1}, 2},    {"z1", {0, 0, 0.05}, {0, 0, -1}, 2}};
  std::size_t wall_contacts = 0;
  for (const auto& w : walls)
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.radius[i] - w.distance(p.position(i)) > 0.0) ++wall_contacts;
  EXPECT_GT(wall_contacts, 900u);
  std::vector<cdm::ContactPair> pairs;
  cdm::AllPairsSearch().find_contacts(p, 0.0, pairs);
  std::size_t pair_contacts = 0;
  for (const auto& c : pairs) pair_contacts += c.overlap > 0.0;
  cdm::PairTable table(3);
  cdm::PairParams pp;
  pp.kn = 1e3;
  pp.en = 0.9;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) table.set(a, b, pp);
  cdm::ContactModule contact(table, walls, false);
  contact.add_forces(p, 1e-6);
  EXPECT_EQ(contact.active_contacts(), pair_contacts + wall_contacts);
}

}  // namespace
