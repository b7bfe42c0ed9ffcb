// The O(N) cell-list search finds exactly the contacts of the O(N^2) all-pairs
// reference: >= 10,000 random polydisperse particles, some touching walls; and with
// periodic boundaries, where contacts reach across the faces to the nearest image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <type_traits>

#include <omp.h>

#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/neighbour_search.hpp"
#include "cdm/solver/parallel.hpp"

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

// A random ranking of n particles: order[k] is the particle of rank k, rank[i] the rank of i.
struct RandomRanks {
  std::vector<std::uint32_t> order, rank;
};

RandomRanks random_ranks(std::size_t n, std::uint64_t seed) {
  RandomRanks r{std::vector<std::uint32_t>(n), std::vector<std::uint32_t>(n)};
  for (std::size_t i = 0; i < n; ++i) r.order[i] = static_cast<std::uint32_t>(i);
  std::shuffle(r.order.begin(), r.order.end(), std::mt19937_64(seed));
  for (std::size_t k = 0; k < n; ++k) r.rank[r.order[k]] = static_cast<std::uint32_t>(k);
  return r;
}

/// The same pairs in the same order; where both carry overlaps, the same overlaps.
template <class A, class B>
void expect_same(const std::vector<A>& a, const std::vector<B>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].i, b[k].i) << k;
    ASSERT_EQ(a[k].j, b[k].j) << k;
    if constexpr (std::is_same_v<A, cdm::ContactPair> && std::is_same_v<B, cdm::ContactPair>) {
      ASSERT_EQ(a[k].overlap, b[k].overlap) << k;  // bit for bit: the same arithmetic
    }
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

TEST(NeighbourSearch, KeyedRowsListEachPairOnceFromTheLowerRankInRankOrder) {
  // Rows of their own (VerletList::key_order's): every particle ranked by a random
  // permutation, the rows the particles of ranks [2000, 9000) in rank order. Each pair
  // with a row particle of the lower rank is listed once, from it, (i, j) = (that row's
  // particle, its partner), the pairs in (rank i, rank j) order: the all-pairs reference's
  // pairs with the lower-ranked particle among the rows, so ordered.
  const cdm::ParticleStore p = random_packing(12000, 9, 0.05, 0.5e-3, 2e-3);
  const auto [order, rank] = random_ranks(p.size(), 3);
  const std::vector<std::uint32_t> rows(order.begin() + 2000, order.begin() + 9000);
  std::vector<cdm::ContactPair> brute;
  cdm::AllPairsSearch().find_contacts(p, 0.2e-3, brute);
  std::vector<cdm::ContactPair> expected;
  for (cdm::ContactPair c : brute) {
    if (rank[c.j] < rank[c.i]) std::swap(c.i, c.j);
    if (rank[c.i] >= 2000 && rank[c.i] < 9000) expected.push_back(c);
  }
  std::sort(expected.begin(), expected.end(), [&](const cdm::ContactPair& a, const cdm::ContactPair& b) {
    return rank[a.i] != rank[b.i] ? rank[a.i] < rank[b.i] : rank[a.j] < rank[b.j];
  });
  ASSERT_GT(expected.size(), 1000u);
  cdm::CellListSearch cl;
  cl.set_rows({&rows, rank.data()});
  const int threads_before = omp_get_max_threads();
  for (int nt : {1, 2, 3}) {
    omp_set_num_threads(nt);
    std::vector<std::vector<cdm::ListedPair>> chunks;
    cl.find_contacts(p, 0.2e-3, chunks);
    std::vector<cdm::ListedPair> flat;
    for (const auto& c : chunks) flat.insert(flat.end(), c.begin(), c.end());
    ASSERT_EQ(flat.size(), expected.size()) << nt << " threads";
    for (std::size_t k = 0; k < flat.size(); ++k) {
      ASSERT_EQ(flat[k].i, expected[k].i) << k;
      ASSERT_EQ(flat[k].j, expected[k].j) << k;
    }
  }
  omp_set_num_threads(threads_before);
}

TEST(NeighbourSearch, KeyedRowsAmongTheirPointsFindTheSamePairsAsAmongAll) {
  // A divided build searches among the particles of its slabs and the slab either side
  // only (KeyedRows::points): rows more than one interaction range inside those points
  // must list the same pairs, in the same order and to the bit, as among all particles.
  const cdm::ParticleStore p = random_packing(12000, 21, 0.05, 0.5e-3, 2e-3);
  const auto [order, rank] = random_ranks(p.size(), 4);
  std::vector<std::uint32_t> rows, points;
  for (std::uint32_t i : order) {  // the rows in rank order; reach 2 rmax + margin = 4.2 mm
    if (p.x[i] >= 0.015 && p.x[i] < 0.035) points.push_back(i);
    if (p.x[i] >= 0.02 && p.x[i] < 0.03) rows.push_back(i);
  }
  cdm::CellListSearch cl;
  auto listed = [&](const std::vector<std::uint32_t>* among) {
    cl.set_rows({&rows, rank.data(), among});
    std::vector<std::vector<cdm::ListedPair>> chunks;
    cl.find_contacts(p, 0.2e-3, chunks);
    std::vector<cdm::ListedPair> flat;
    for (const auto& c : chunks) flat.insert(flat.end(), c.begin(), c.end());
    return flat;
  };
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::vector<cdm::ListedPair> all = listed(nullptr);
  ASSERT_GT(all.size(), 1000u);
  for (int nt : {1, 2, 3}) {
    omp_set_num_threads(nt);
    expect_same(listed(&points), all);
  }
  omp_set_num_threads(threads_before);
}

TEST(NeighbourSearch, PerThreadChunksConcatenateToTheOneList) {
  // Above the parallel threshold each thread lists its own particles' pairs into a
  // chunk; in order the chunks must be the list one thread makes, for any team size.
  const cdm::ParticleStore p = random_packing(12000, 5, 0.05, 0.5e-3, 2e-3);
  ASSERT_GT(p.size(), cdm::parallel_threshold);
  cdm::CellListSearch cl;
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(1);
  std::vector<cdm::ContactPair> one;
  cl.find_contacts(p, 0.3e-3, one);
  ASSERT_GT(one.size(), 2000u);
  for (int nt : {1, 2, 3}) {
    omp_set_num_threads(nt);
    std::vector<std::vector<cdm::ListedPair>> chunks;
    cl.find_contacts(p, 0.3e-3, chunks);
    ASSERT_EQ(chunks.size(), static_cast<std::size_t>(nt));
    std::vector<cdm::ListedPair> joined;
    for (std::size_t t = 0; t < chunks.size(); ++t) {
      for (const cdm::ListedPair& c : chunks[t]) {  // thread t's own particles i
        EXPECT_GE(c.i, p.size() * t / chunks.size()) << nt << " threads, chunk " << t;
        EXPECT_LT(c.i, p.size() * (t + 1) / chunks.size()) << nt << " threads, chunk " << t;
      }
      joined.insert(joined.end(), chunks[t].begin(), chunks[t].end());
    }
    expect_same(joined, one);
    std::vector<cdm::ContactPair> flat;
    cl.find_contacts(p, 0.3e-3, flat);
    expect_same(flat, one);
  }
  omp_set_num_threads(threads_before);
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

TEST(NeighbourSearch, ALimitStopsTheListingEarlyAndSaysSo) {
  // A pile: 2000 particles within a diameter of one another, ~2e6 pairs. With a limit
  // each run of particles stops once its pairs exceed it, serially and in threads.
  cdm::ParticleStore pile;
  for (int i = 0; i < 2000; ++i) pile.add({1e-5 * (i % 7), 1e-5 * (i % 11), 1e-5 * (i % 13)}, {}, 1e-3, 2500.0, 0);
  cdm::CellListSearch cl;
  std::vector<cdm::ContactPair> all, cut;
  EXPECT_TRUE(cl.find_contacts(pile, 0.0, all));
  EXPECT_EQ(all.size(), 2000u * 1999u / 2u);
  const int threads_before = omp_get_max_threads();
  for (int nt : {1, 2, 3}) {
    omp_set_num_threads(nt);
    EXPECT_FALSE(cl.find_contacts(pile, 0.0, cut, {}, 5000)) << nt << " threads";
    EXPECT_GT(cut.size(), 5000u) << nt << " threads";
    EXPECT_LT(cut.size(), 3u * (5000u + 2000u)) << nt << " threads: each run stops within a row of its limit";
    // The list's first pair is the whole list's first pair: a refusal names the same one.
    EXPECT_EQ(cut.front().i, all.front().i);
    EXPECT_EQ(cut.front().j, all.front().j);
    EXPECT_FALSE(cl.find_contacts(pile, 0.0, cut, {}, 0));
    EXPECT_TRUE(cl.find_contacts(pile, 0.0, cut, {}, all.size()));
    EXPECT_EQ(cut.size(), all.size());
  }
  omp_set_num_threads(threads_before);
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
  std::vector<cdm::Wall> walls = {
      cdm::Wall::plane("x0", {0, 0, 0}, {1, 0, 0}, 2),    cdm::Wall::plane("x1", {0.05, 0, 0}, {-1, 0, 0}, 2), cdm::Wall::plane("y0", {0, 0, 0}, {0, 1, 0}, 2),
      cdm::Wall::plane("y1", {0, 0.05, 0}, {0, -1, 0}, 2), cdm::Wall::plane("z0", {0, 0, 0}, {0, 0, 1}, 2),    cdm::Wall::plane("z1", {0, 0, 0.05}, {0, 0, -1}, 2)};
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

// Periodic along x and y (z bounded): the cell list, whose cells tile each period, finds
// exactly the all-pairs search's nearest-image contacts, including those across the
// faces — a tenth of the particles are placed straddling a face or a corner.
TEST(NeighbourSearch, PeriodicCellListEqualsAllPairs) {
  cdm::PeriodicBox box;
  box.on[0] = box.on[1] = true;
  box.lo[0] = -0.01; box.len[0] = 0.05;
  box.lo[1] = 0.0; box.len[1] = 0.03;
  cdm::ParticleStore p = random_packing(12000, 5, 0.05, 0.5e-3, 2e-3);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.x[i] = box.wrap(p.x[i] - 0.01, 0);
    p.y[i] = box.wrap(0.6 * p.y[i], 1);
    if (i % 10 == 0) p.x[i] = box.wrap(box.lo[0] + (u(rng) < 0.5 ? 1.0 : -1.0) * 1.5e-3 * u(rng), 0);
    if (i % 20 == 0) p.y[i] = box.wrap(box.lo[1] + (u(rng) < 0.5 ? 1.0 : -1.0) * 1.5e-3 * u(rng), 1);
  }
  std::vector<cdm::ContactPair> cells, brute, open;
  cdm::CellListSearch cl;
  for (double margin : {0.0, 0.3e-3}) {
    cl.find_contacts(p, margin, cells, box);
    cdm::AllPairsSearch().find_contacts(p, margin, brute, box);
    cdm::AllPairsSearch().find_contacts(p, margin, open);
    EXPECT_GT(brute.size(), open.size() + 100) << "contacts across the faces must be found";
    expect_same(cells, brute);
  }
  // A period of only two or one cells (each neighbouring cell visited once).
  box.len[1] = 0.009;
  box.len[0] = 0.005;
  cdm::ParticleStore q;
  for (std::size_t i = 0; i < 300; ++i)
    q.add({box.lo[0] + box.len[0] * u(rng), box.len[1] * u(rng), 0.02 * u(rng)}, {}, 0.9e-3 + 0.2e-3 * u(rng), 2500.0, 0);
  cl.find_contacts(q, 0.1e-3, cells, box);
  cdm::AllPairsSearch().find_contacts(q, 0.1e-3, brute, box);
  expect_same(cells, brute);
}

// Two materials with the same linear law: random_packing alternates materials 0 and 1.
cdm::PairTable linear_table() {
  cdm::PairTable table(2);
  cdm::PairParams pp;
  pp.kn = 1e3;
  pp.en = 0.9;
  pp.mu = 0.5;
  for (int a = 0; a < 2; ++a)
    for (int b = a; b < 2; ++b) table.set(a, b, pp);
  return table;
}

// A pair touching across the x face gets, bit for bit, the forces and torques of the
// same pair in the interior; momentum is conserved over a periodic random packing.
TEST(PeriodicContacts, ForceAcrossTheFaceEqualsInteriorForce) {
  cdm::PeriodicBox box;
  box.on[0] = true;
  box.lo[0] = 0.0;
  box.len[0] = 0.02;
  auto pair_forces = [&](double x1, double x2) {
    cdm::ParticleStore p;
    p.enable_rotation();
    p.add({x1, 0.01, 0.01}, {0.1, 0.02, 0.0}, 1e-3, 2500.0, 0);
    p.add({x2, 0.0105, 0.01}, {-0.1, 0.0, 0.03}, 1e-3, 2500.0, 0);
    p.set_angular_velocity(0, {1.0, 2.0, 3.0});
    cdm::ContactModule c(linear_table(), {}, true, 0.2e-3);
    c.set_periodic_box(box);
    c.add_forces(p, 1e-6);
    c.add_forces(p, 1e-6);  // twice: the tangential history grows
    EXPECT_EQ(c.active_contacts(), 1u);
    return std::vector<double>{p.fx[0], p.fy[0], p.fz[0], p.fx[1], p.fy[1], p.fz[1], p.tx[0], p.ty[0], p.tz[0], p.tx[1]};
  };
  // Centres 1.9 mm apart along x (overlap 0.1 mm): inside, and across x = 0 / 0.02. The
  // positions are exact binary fractions apart so the separations agree bit for bit.
  const double s = 0.0019;
  const auto inside = pair_forces(0.01 - 0.5 * s, 0.01 + 0.5 * s);
  const auto across = pair_forces(0.02 - 0.5 * s, 0.5 * s);
  for (std::size_t k = 0; k < inside.size(); ++k) EXPECT_NEAR(across[k], inside[k], 1e-12 * std::abs(inside[0])) << k;
  EXPECT_NE(inside[0], 0.0);

  cdm::ParticleStore p = random_packing(3000, 11, 0.02, 0.5e-3, 1e-3);
  p.enable_rotation();  // friction makes torque
  cdm::PeriodicBox all;
  for (int a = 0; a < 3; ++a) { all.on[a] = true; all.len[a] = 0.02; }
  cdm::ContactModule c(linear_table(), {}, true, 0.1e-3);
  c.set_periodic_box(all);
  for (std::size_t i = 0; i < p.size(); ++i) p.vx[i] = 0.01 * std::sin(static_cast<double>(i));
  c.add_forces(p, 1e-6);
  double fx = 0, fy = 0, fz = 0, fabs = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    fx += p.fx[i]; fy += p.fy[i]; fz += p.fz[i];
    fabs += std::abs(p.fx[i]);
  }
  EXPECT_GT(c.active_contacts(), 500u);
  EXPECT_LT(std::abs(fx) + std::abs(fy) + std::abs(fz), 1e-12 * fabs);
}

// A fixed particle is an immovable body in contacts: against a mobile one, the force is
// that of a wall (m* = the mobile particle's mass); two fixed particles are not listed.
TEST(PeriodicContacts, FixedParticlesActAsInfiniteMass) {
  cdm::ParticleStore p;
  p.add({0.0, 0.0, 0.0}, {}, 1e-3, 2500.0, 0, true);
  p.add({0.0, 0.0019, 0.0}, {0.0, -0.1, 0.0}, 1e-3, 2500.0, 0);
  p.add({0.0019, 0.0, 0.0}, {}, 1e-3, 2500.0, 0, true);  // overlaps the first: not a contact
  cdm::ContactModule c(linear_table(), {}, false);
  c.add_forces(p, 1e-6);
  EXPECT_EQ(c.list().size(), 1u);
  cdm::ParticleStore w;
  w.add({0.0, 0.0019, 0.0}, {0.0, -0.1, 0.0}, 1e-3, 2500.0, 0);
  cdm::ContactModule cw(linear_table(), {cdm::Wall::plane("floor", {0.0, 0.001, 0.0}, {0.0, 1.0, 0.0}, 0)}, false);
  cw.add_forces(w, 1e-6);
  EXPECT_DOUBLE_EQ(p.fy[1], w.fy[0]);
  EXPECT_DOUBLE_EQ(p.fy[0], -w.fy[0]);
}

// With every free particle of one mass the linear law's damping comes from a table per
// material pair (m* = m/2, or m against a fixed particle); it must equal, bit for bit,
// the damping taken per contact, which a single particle of another mass brings back.
TEST(PeriodicContacts, CommonMassDampingEqualsPerContactDamping) {
  cdm::ParticleStore p = random_packing(3000, 13, 0.02, 0.5e-3, 0.5e-3);
  for (int k = 0; k < 200; ++k)  // fixed particles among them
    p.add({0.001 * (k % 20), 0.001 * (k / 20), 0.0}, {}, 0.5e-3, 2500.0, k % 2, true);
  p.enable_rotation();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.inv_mass[i] != 0.0) { p.vx[i] = u(rng); p.vz[i] = u(rng); p.wy[i] = 100.0 * u(rng); }
  cdm::PairTable pairs(2);
  for (int a = 0; a < 2; ++a)
    for (int b = a; b < 2; ++b) {
      cdm::PairParams pp;
      pp.kn = 1e3 * (1 + a + 2 * b); pp.en = 0.9 - 0.1 * (a + b); pp.kt_factor = 2.0 / 7.0; pp.etat_factor = 0.5;
      pp.mu = 0.5;
      pairs.set(a, b, pp);
    }
  std::vector<cdm::Wall> walls{cdm::Wall::plane("floor", {0, 0, 0}, {0, 0, 1}, 1)};
  cdm::ParticleStore q = p;
  q.mass[0] *= 1.5;  // one free particle of another mass: damping per contact for all
  q.inv_mass[0] = 1.0 / q.mass[0];
  cdm::ContactModule table(pairs, walls, true, 0.1e-3), per_contact(pairs, walls, true, 0.1e-3);
  for (int step = 0; step < 2; ++step) {  // twice: the tangential history grows
    p.clear_forces(); q.clear_forces();
    table.add_forces(p, 1e-6);
    per_contact.add_forces(q, 1e-6);
  }
  std::size_t compared = 0, fixed_partners = 0;
  for (std::size_t i = 1; i < p.size(); ++i) {
    const double dx = p.x[i] - p.x[0], dy = p.y[i] - p.y[0], dz = p.z[i] - p.z[0];
    if (dx * dx + dy * dy + dz * dz < 1.21e-6) continue;  // within reach of particle 0
    if (p.fx[i] == 0.0) continue;
    ++compared;
    ASSERT_EQ(p.fx[i], q.fx[i]) << i;
    ASSERT_EQ(p.fy[i], q.fy[i]) << i;
    ASSERT_EQ(p.fz[i], q.fz[i]) << i;
    ASSERT_EQ(p.ty[i], q.ty[i]) << i;
    fixed_partners += p.inv_mass[i] == 0.0;
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_GT(fixed_partners, 10u);  // pairs of a fixed and a free particle were compared
}

}  // namespace

// Spatial sorting: ParticleStore::permute moves every field with its particle and keeps
// identities; VerletList::spatial_order is a permutation that puts the particles of
// one cell next to each other, slab axis slowest; and forces evaluated on the permuted
// store (module state permuted alike) are the unsorted ones, particle by particle.
TEST(SpatialSort, PermuteMovesEveryFieldWithItsParticle) {
  cdm::ParticleStore p = random_packing(500, 7, 0.01, 0.2e-3, 0.3e-3);
  p.enable_rotation();
  p.enable_two_way();
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.vx[i] = 1.0 * i; p.fz[i] = 2.0 * i; p.wy[i] = 3.0 * i; p.jx[i] = 4.0 * i;
  }
  const cdm::ParticleStore before = p;
  std::vector<std::uint32_t> from(p.size());
  for (std::size_t i = 0; i < from.size(); ++i) from[i] = static_cast<std::uint32_t>((7 * i + 3) % from.size());
  p.permute(from);
  p.permute(from);  // twice: identities compose
  const cdm::IdentityOrder order(p);
  for (std::size_t s = 0; s < p.size(); ++s) {
    const std::size_t k = p.id_of(s);
    ASSERT_EQ(order.slot_of(k), s);
    EXPECT_EQ(k, from[from[s]]);
    EXPECT_EQ(p.x[s], before.x[k]); EXPECT_EQ(p.radius[s], before.radius[k]); EXPECT_EQ(p.mass[s], before.mass[k]);
    EXPECT_EQ(p.material[s], before.material[k]); EXPECT_EQ(p.inv_inertia[s], before.inv_inertia[k]);
    EXPECT_EQ(p.vx[s], before.vx[k]); EXPECT_EQ(p.fz[s], before.fz[k]); EXPECT_EQ(p.wy[s], before.wy[k]);
    EXPECT_EQ(p.jx[s], before.jx[k]);
  }
}

TEST(SpatialSort, OrderIsAPermutationByCellsAndForcesFollowTheParticles) {
  using namespace cdm;
  ParticleStore p = random_packing(6000, 11, 0.02, 0.4e-3, 0.6e-3);
  p.enable_rotation();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (std::size_t i = 0; i < p.size(); ++i) { p.vx[i] = u(rng); p.vy[i] = u(rng); p.wz[i] = 100.0 * u(rng); }
  PairTable pairs(2);
  for (int a = 0; a < 2; ++a)
    for (int b = a; b < 2; ++b) {
      PairParams pp;
      pp.kn = 1e3; pp.en = 0.9; pp.kt_factor = 2.0 / 7.0; pp.etat_factor = 0.5; pp.mu = 0.5;
      pairs.set(a, b, pp);
    }
  std::vector<Wall> walls{cdm::Wall::plane("floor", {0, 0, 0}, {0, 0, 1}, 0)};
  ContactModule plain(pairs, walls, true, 0.1e-3), sorted(pairs, walls, true, 0.1e-3);
  ParticleStore q = p;
  // Two evaluations each (history builds up), then sort q and its module, then more.
  auto advance = [](ParticleStore& s) {
    for (std::size_t i = 0; i < s.size(); ++i) { s.x[i] += 1e-6 * s.vx[i]; s.y[i] += 1e-6 * s.vy[i]; }
  };
  for (int step = 0; step < 4; ++step) {
    if (step == 2) {
      const std::vector<std::uint32_t> from = sorted.list().spatial_order(q);
      std::vector<std::uint8_t> seen(from.size(), 0);
      for (std::uint32_t k : from) { ASSERT_LT(k, from.size()); ASSERT_FALSE(seen[k]); seen[k] = 1; }
      q.permute(from);
      sorted.permute(from);
      // Sorted: the cell coordinate (cells one interaction range wide, 2 r_max + skin,
      // from the lowest centre) never decreases along the slab axis.
      const std::vector<double>* c[3] = {&q.x, &q.y, &q.z};
      const double h = 2.0 * *std::max_element(q.radius.begin(), q.radius.end()) + 0.1e-3;
      int axis = -1;
      for (int a = 0; a < 3 && axis < 0; ++a) {
        const double lo = *std::min_element(c[a]->begin(), c[a]->end());
        bool mono = true;
        for (std::size_t s = 1; s < q.size() && mono; ++s)
          mono = std::floor(((*c[a])[s] - lo) / h) >= std::floor(((*c[a])[s - 1] - lo) / h);
        if (mono) axis = a;
      }
      EXPECT_GE(axis, 0) << "no axis along which the sorted order is monotone to one cell";
    }
    p.clear_forces(); q.clear_forces();
    plain.add_forces(p, 1e-6);
    sorted.add_forces(q, 1e-6);
    for (std::size_t s = 0; s < q.size(); ++s) {
      const std::size_t k = q.id_of(s);
      const double scale = 1e-12 * (1.0 + std::abs(p.fx[k]) + std::abs(p.fy[k]) + std::abs(p.fz[k]));
      ASSERT_NEAR(q.fx[s], p.fx[k], scale) << "step " << step << " particle " << k;
      ASSERT_NEAR(q.fy[s], p.fy[k], scale) << "step " << step << " particle " << k;
      ASSERT_NEAR(q.fz[s], p.fz[k], scale) << "step " << step << " particle " << k;
      ASSERT_NEAR(q.tz[s], p.tz[k], 1e-12 * (1.0 + std::abs(p.tz[k]))) << "step " << step << " particle " << k;
    }
    EXPECT_EQ(plain.active_contacts(), sorted.active_contacts());
    advance(p); advance(q);
  }
  EXPECT_GT(plain.active_contacts(), 100u);
}

// The minimum image is d − L·nearbyint(d/L), bit for bit, signed zeros included: the
// inline rounding for |d| < 1.5 L (decided by comparing |d| with L/2 and 3L/2, not by
// dividing) must not change a trajectory. Ties (d = ±L/2, ±3L/2) round to even as
// nearbyint does, the neighbouring doubles too; |d| ≥ 1.5 L and non-finite d go to
// nearbyint. (Only a d whose quotient d/L rounds onto a tie without being one may get
// the other, equally near, image.)
TEST(PeriodicBox, MinimumImageIsNearbyintBitForBit) {
  cdm::PeriodicBox box;
  box.on[1] = true;
  box.len[1] = 0.022;
  auto reference = [&](double d) { return d - box.len[1] * std::nearbyint(d / box.len[1]); };
  auto same_bits = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  std::vector<double> ds{0.0, -0.0, 1e-300, -1e-300, 0.011, -0.011, 0.033, -0.033, 0.022, -0.022, 0.044, -0.05,
                         std::nextafter(0.011, 1.0), std::nextafter(0.011, 0.0), std::nextafter(-0.033, 0.0),
                         std::nextafter(-0.033, -1.0), 1e3, -1e3, std::numeric_limits<double>::infinity(),
                         std::numeric_limits<double>::quiet_NaN()};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (int k = 0; k < 100000; ++k) ds.push_back(u(rng));
  for (double d : ds) {
    const double got = box.min_image(d, 1), want = reference(d);
    if (std::isnan(want)) EXPECT_TRUE(std::isnan(got)) << d;
    else EXPECT_TRUE(same_bits(got, want)) << d << ": " << got << " against " << want;
  }
  EXPECT_TRUE(same_bits(box.min_image(-0.0, 0), -0.0));  // a non-periodic axis is untouched
}

// The tangential spring of a contact that lasts is carried across list rebuilds: a
// module that rebuilds at every evaluation (skin 0) must give, bit for bit, the forces
// and torques of one that builds once (a skin wider than the motion), while a pair
// slides past another, a third particle in contact with it and a fourth far away, so
// that the carried rows are not all the first. Dropping the history at a rebuild
// restarts the spring from one step's slip.
TEST(ContactHistory, CarriedAcrossRebuilds) {
  auto scene = [] {
    cdm::ParticleStore p;
    p.enable_rotation();
    p.add({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, 1e-3, 2500.0, 0);
    p.add({1.9e-3, 0.0, 0.0}, {0.0, 0.02, 0.0}, 1e-3, 2500.0, 0);      // slides along y
    p.add({0.0, 1.95e-3, 0.0}, {0.0, 0.0, -0.01}, 1e-3, 2500.0, 0);    // slides along z
    p.add({0.02, 0.02, 0.02}, {0.0, 0.0, 0.0}, 1e-3, 2500.0, 0);       // alone
    return p;
  };
  cdm::PairTable table(1);
  cdm::PairParams pp;
  pp.kn = 1e3;
  pp.en = 0.9;
  pp.mu = 0.5;
  table.set(0, 0, pp);
  cdm::ContactModule every(table, {}, true, 0.0), once(table, {}, true, 1e-3);
  cdm::ParticleStore a = scene(), b = scene();
  const double dt = 1e-6;
  for (int step = 0; step < 200; ++step) {
    for (cdm::ParticleStore* p : {&a, &b}) {
      for (std::size_t i = 0; i < p->size(); ++i) {  // prescribed motion; forces afresh
        p->x[i] += dt * p->vx[i]; p->y[i] += dt * p->vy[i]; p->z[i] += dt * p->vz[i];
        p->fx[i] = p->fy[i] = p->fz[i] = p->tx[i] = p->ty[i] = p->tz[i] = 0.0;
      }
    }
    every.add_forces(a, dt);
    once.add_forces(b, dt);
    ASSERT_EQ(every.active_contacts(), 2u) << "step " << step;
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a.fy[i], b.fy[i]) << "particle " << i << ", step " << step;
      ASSERT_EQ(a.fz[i], b.fz[i]) << "particle " << i << ", step " << step;
      ASSERT_EQ(a.tz[i], b.tz[i]) << "particle " << i << ", step " << step;
      ASSERT_EQ(a.ty[i], b.ty[i]) << "particle " << i << ", step " << step;
    }
  }
  // The springs did build up: 200 steps of slip at 0.02 m/s stretch particle 1's to
  // 4e-6 m, kt = 0.4 kn (the default kt_factor) times that is 1.6e-3 N, below the
  // Coulomb limit μ F_n = 0.5 × 0.1 N.
  EXPECT_NEAR(a.fy[1], -0.4 * 1e3 * 200 * dt * 0.02, 2e-4);
}
