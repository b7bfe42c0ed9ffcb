#include "cdm/solver/placement.hpp"

#include <algorithm>
#include <limits>
#include <cmath>

namespace cdm {

SequentialPlacement::SequentialPlacement(double r_max, const std::vector<Wall>& walls,
                                         const std::vector<TriangleMesh>& meshes, double t, const PeriodicBox& box)
    : cell_(r_max > 0.0 ? 2.0 * r_max : 1.0), time_(t), box_(box) {
  walls_.reserve(walls.size());
  for (const Wall& w : walls) walls_.push_back(w.at(t));
  if (!meshes.empty()) {
    meshes_ = std::make_unique<MeshContacts>(meshes);
    meshes_->build_grid(r_max);
  }
}

namespace {
/// Cell coordinates packed 21 bits per axis (they wrap beyond ±2^20 cells: a far cell
/// then shares a key, and the distance test still decides).
std::uint64_t pack(std::int64_t a, std::int64_t b, std::int64_t c) {
  constexpr std::uint64_t m = 0x1FFFFF;
  return ((static_cast<std::uint64_t>(a) & m) << 42) | ((static_cast<std::uint64_t>(b) & m) << 21) |
         (static_cast<std::uint64_t>(c) & m);
}
}  // namespace

std::int64_t SequentialPlacement::cell(double v) const {
  return static_cast<std::int64_t>(std::clamp(std::floor(v / cell_), -0x1p62, 0x1p62));  // clamped: no overflow
}

bool SequentialPlacement::clear_of_spheres(Vec3 x, double r) const {
  const std::int64_t cx = cell(x.x), cy = cell(x.y), cz = cell(x.z);
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c) {
        const auto it = cells_.find(pack(cx + a, cy + b, cz + c));
        if (it == cells_.end()) continue;
        for (const Sphere& s : it->second) {
          const Vec3 d = x - s.x;
          if (dot(d, d) < (r + s.r) * (r + s.r)) return false;
        }
      }
  return true;
}

bool SequentialPlacement::clear(Vec3 x, double r) const {
  for (const auto& w : walls_)
    if (w.gap(x, std::numeric_limits<double>::infinity()).gap < r) return false;
  if (meshes_) {
    thread_local std::vector<MeshContacts::Contact> touching;
    touching.clear();
    meshes_->find(x, r, 0, touching, time_);
    if (!touching.empty()) return false;
  }
  // The sphere and, along each periodic axis where it is within a contact distance of a
  // face, its image through the other face.
  double shift[3][2] = {{0, 0}, {0, 0}, {0, 0}};
  int count[3] = {1, 1, 1};
  const double c[3] = {x.x, x.y, x.z};
  for (int a = 0; a < 3; ++a) {
    if (!box_.on[a]) continue;
    if (c[a] - box_.lo[a] < cell_) shift[a][count[a]++] = box_.len[a];
    else if (box_.lo[a] + box_.len[a] - c[a] < cell_) shift[a][count[a]++] = -box_.len[a];
  }
  for (int i = 0; i < count[0]; ++i)
    for (int j = 0; j < count[1]; ++j)
      for (int k = 0; k < count[2]; ++k)
        if (!clear_of_spheres(x + Vec3{shift[0][i], shift[1][j], shift[2][k]}, r)) return false;
  return true;
}

void SequentialPlacement::add(Vec3 x, double r) { cells_[pack(cell(x.x), cell(x.y), cell(x.z))].push_back({x, r}); }

}  // namespace cdm
