// Random sequential addition's test of a new sphere (SequentialPlacement::clear) against
// every sphere added before, checked pair by pair: thousands of polydisperse spheres
// (the cell table grows many times), candidates anywhere in and around them, a periodic
// box whose images count, and cells far enough apart that their packed keys coincide.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "cdm/solver/placement.hpp"

namespace {

struct Ball {
  cdm::Vec3 x;
  double r;
};

/// Whether a sphere of radius @p r at @p x overlaps none of @p placed (touching is clear),
/// by the nearest images where @p box is periodic.
bool clear_by_pairs(const std::vector<Ball>& placed, cdm::Vec3 x, double r, const cdm::PeriodicBox& box) {
  for (const Ball& b : placed) {
    const cdm::Vec3 d{box.min_image(x.x - b.x.x, 0), box.min_image(x.y - b.x.y, 1), box.min_image(x.z - b.x.z, 2)};
    if (cdm::dot(d, d) < (r + b.r) * (r + b.r)) return false;
  }
  return true;
}

void fill_and_probe(const cdm::PeriodicBox& box, double side, std::uint64_t seed) {
  const double r_max = 1.0e-3;
  cdm::SequentialPlacement placement(r_max, {}, {}, 0.0, box);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto random_ball = [&](double margin) {
    const double r = r_max * (0.3 + 0.7 * u(rng));
    return Ball{{side * u(rng) - margin, side * u(rng) - margin, side * u(rng) - margin}, r};
  };
  std::vector<Ball> placed;
  std::size_t refused = 0;
  while (placed.size() < 4000) {
    const Ball b = random_ball(0.0);
    const bool clear = placement.clear(b.x, b.r);
    ASSERT_EQ(clear, clear_by_pairs(placed, b.x, b.r, box)) << "after " << placed.size() << " spheres";
    if (!clear) {
      ++refused;
      continue;
    }
    placement.add(b.x, b.r);
    placed.push_back(b);
  }
  EXPECT_GT(refused, 500u);  // a dense enough fill that many candidates meet a sphere
  // Candidates beyond the filled cube too (the cells around it are empty).
  for (int k = 0; k < 20000; ++k) {
    const Ball b = random_ball(0.1 * side);
    ASSERT_EQ(placement.clear(b.x, b.r), clear_by_pairs(placed, b.x, b.r, box)) << "candidate " << k;
  }
}

TEST(SequentialPlacement, ClearIffNoEarlierSphereOverlaps) { fill_and_probe({}, 0.04, 7); }

TEST(SequentialPlacement, PeriodicImagesCount) {
  cdm::PeriodicBox box;
  box.on[0] = box.on[2] = true;
  box.len[0] = box.len[2] = 0.04;
  fill_and_probe(box, 0.04, 11);
}

TEST(SequentialPlacement, FarCellsSharingAKeyDoNotBlockEachOther) {
  // Cells are 2 r_max wide and packed 21 bits an axis: 2^21 cells apart along x, two
  // spheres share a cell key, and only the distance decides.
  const double r_max = 1.0e-3, far = 2.0 * r_max * double(1 << 21);
  cdm::SequentialPlacement placement(r_max, {}, {}, 0.0, {});
  placement.add({0.0, 0.0, 0.0}, r_max);
  EXPECT_TRUE(placement.clear({far, 0.0, 0.0}, r_max));
  EXPECT_FALSE(placement.clear({1.5 * r_max, 0.0, 0.0}, r_max));
  placement.add({far, 0.0, 0.0}, r_max);
  EXPECT_FALSE(placement.clear({far + 1.5 * r_max, 0.0, 0.0}, r_max));
  EXPECT_TRUE(placement.clear({2.0 * r_max, 0.0, 0.0}, r_max));  // touching is clear
}

}  // namespace
