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

std::size_t SequentialPlacement::slot_of(std::uint64_t key) const {
  const std::size_t mask = table_.size() - 1;
  std::size_t k = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 32) & mask;
  while (table_[k].head != 0 && table_[k].key != key) k = (k + 1) & mask;
  return k;
}

bool SequentialPlacement::clear_of_spheres(Vec3 x, double r) const {
  const std::int64_t cx = cell(x.x), cy = cell(x.y), cz = cell(x.z);
  // The sphere's own cell first, where an overlap is likeliest: a rejected candidate,
  // the common case in a dense fill, costs one lookup (the answer is the same in any order).
  static constexpr int order[3] = {0, -1, 1};
  for (const int a : order)
    for (const int b : order)
      for (const int c : order) {
        for (std::uint32_t q = table_[slot_of(pack(cx + a, cy + b, cz + c))].head; q != 0; q = next_[q - 1]) {
          const Sphere& s = spheres_[q - 1];
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

void SequentialPlacement::add(Vec3 x, double r) {
  if (2 * (occupied_ + 1) > table_.size()) {  // grow: every occupied cell into a table twice the size
    std::vector<Cell> old(2 * table_.size());
    old.swap(table_);
    for (const Cell& c : old)
      if (c.head != 0) table_[slot_of(c.key)] = c;
  }
  spheres_.push_back({x, r});
  const std::uint64_t key = pack(cell(x.x), cell(x.y), cell(x.z));
  Cell& c = table_[slot_of(key)];
  if (c.head == 0) ++occupied_;
  c.key = key;
  next_.push_back(c.head);
  c.head = static_cast<std::uint32_t>(spheres_.size());
}

}  // namespace cdm
