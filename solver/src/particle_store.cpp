#include "cdm/solver/particle_store.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <numbers>

namespace cdm {

namespace {

// Every per-particle array of doubles (empty where the scene does not carry it).
template <class Store>
auto double_arrays(Store& p) {
  return std::array{&p.x,  &p.y,  &p.z,  &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz, &p.radius, &p.mass, &p.inv_mass,
                    &p.wx, &p.wy, &p.wz, &p.tx, &p.ty, &p.tz, &p.inv_inertia, &p.drag_k, &p.ugx, &p.ugy, &p.ugz,
                    &p.dfx, &p.dfy, &p.dfz, &p.jx, &p.jy, &p.jz};
}

}  // namespace

void ParticleStore::enable_rotation() {
  rotation_enabled_ = true;
  const std::size_t n = size();
  for (auto* v : {&wx, &wy, &wz, &tx, &ty, &tz}) assign_zeroed(*v, n);
  inv_inertia.resize(n);
  for (std::size_t i = 0; i < n; ++i) inv_inertia[i] = inverse_inertia(i);
}

double ParticleStore::inverse_inertia(std::size_t i) const {
  // A solid sphere's I = m d²/10.
  const double d = 2.0 * radius[i];
  return is_fixed(i) || mass[i] == 0.0 ? 0.0 : 10.0 / (mass[i] * d * d);
}

void ParticleStore::enable_drag_relaxation() {
  drag_relaxation_enabled_ = true;
  const std::size_t n = size();
  for (auto* v : {&drag_k, &ugx, &ugy, &ugz}) assign_zeroed(*v, n);
}

void ParticleStore::enable_two_way() {
  two_way_enabled_ = true;
  const std::size_t n = size();
  for (auto* v : {&dfx, &dfy, &dfz, &jx, &jy, &jz}) assign_zeroed(*v, n);
}

void ParticleStore::reserve(std::size_t n) {
  std::vector<std::vector<double>*> grown = {&x, &y, &z, &vx, &vy, &vz, &fx, &fy, &fz, &radius, &mass, &inv_mass};
  if (two_way_enabled_) grown.insert(grown.end(), {&dfx, &dfy, &dfz, &jx, &jy, &jz});
  if (drag_relaxation_enabled_) grown.insert(grown.end(), {&drag_k, &ugx, &ugy, &ugz});
  if (rotation_enabled_) grown.insert(grown.end(), {&wx, &wy, &wz, &tx, &ty, &tz, &inv_inertia});
  for (auto* a : grown) reserve_zeroed(*a, n);
  material.reserve(n);
}

void ParticleStore::add(Vec3 p, Vec3 v, double r, double density, int mat, bool fixed) {
  append(p, r, mat, fixed);
  const std::size_t i = size() - 1;
  vx[i] = v.x; vy[i] = v.y; vz[i] = v.z;
  set_mass(i, density);
}

void ParticleStore::append(Vec3 p, double r, int mat, bool fixed) {
  // Grown by doubling, as push_back would, but without committing the pages of the
  // slots whose values this process does not hold (zero, slot_pages.hpp).
  const std::size_t n = size();
  if (n > 0)
    for (auto* a : double_arrays(*this))
      if (a->size() == n && a->capacity() == n) reserve_zeroed(*a, 2 * n);
  x.push_back(p.x); y.push_back(p.y); z.push_back(p.z);
  for (auto* a : {&vx, &vy, &vz, &fx, &fy, &fz, &mass, &inv_mass}) a->push_back(0.0);
  radius.push_back(r);
  material.push_back(static_cast<std::uint8_t>(mat));
  if (fixed && fixed_flag.empty()) fixed_flag.resize(n, 0);
  if (fixed || !fixed_flag.empty()) fixed_flag.push_back(fixed ? 1 : 0);
  if (!id.empty()) id.push_back(static_cast<std::uint32_t>(id.size()));
  if (two_way_enabled_)
    for (auto* a : {&dfx, &dfy, &dfz, &jx, &jy, &jz}) a->push_back(0.0);
  if (drag_relaxation_enabled_)
    for (auto* a : {&drag_k, &ugx, &ugy, &ugz}) a->push_back(0.0);
  if (rotation_enabled_)
    for (auto* a : {&wx, &wy, &wz, &tx, &ty, &tz, &inv_inertia}) a->push_back(0.0);
}

void ParticleStore::set_mass(std::size_t i, double density) {
  const double d = 2.0 * radius[i];
  const double m = density * std::numbers::pi * d * d * d / 6.0;
  mass[i] = m;
  inv_mass[i] = is_fixed(i) ? 0.0 : 1.0 / m;
  if (rotation_enabled_) inv_inertia[i] = inverse_inertia(i);
}

std::size_t ParticleStore::bytes() const {
  std::size_t b = 0;
  for (const auto* v : double_arrays(*this))
    b += v->size() * sizeof(double);
  b += material.size() + fixed_flag.size();
  b += id.size() * sizeof(std::uint32_t);
  return b;
}

void ParticleStore::permute(const std::vector<std::uint32_t>& from) {
  const std::size_t n = size();
  if (id.empty()) {
    id.resize(n);
    for (std::size_t i = 0; i < n; ++i) id[i] = static_cast<std::uint32_t>(i);
  }
  permute_state(from);
  std::vector<std::uint32_t> ids;
  permute_array(id, from, ids);
}

void ParticleStore::permute_state(const std::vector<std::uint32_t>& from) {
  const std::size_t n = size();
  std::vector<double> tmp;
  for (auto* v : double_arrays(*this))
    if (v->size() == n) permute_array(*v, from, tmp);  // else a field this scene does not carry
  std::vector<std::uint8_t> mat;
  permute_array(material, from, mat);
  std::vector<std::uint8_t> flags;
  if (!fixed_flag.empty()) permute_array(fixed_flag, from, flags);
}

void ParticleStore::keep(const std::vector<std::uint32_t>& from) {
  const std::size_t n = size(), m = from.size();
  permute_state(from);
  if (id.empty()) return;  // never sorted: identities are the slots, kept in order
  // Rank of each identity left among those left.
  std::vector<std::uint32_t> rank(n, 0);
  for (std::uint32_t i : from) rank[id[i]] = 1;
  std::uint32_t r = 0;
  for (std::size_t k = 0; k < n; ++k) rank[k] = rank[k] ? r++ : 0;
  std::vector<std::uint32_t> ids(m);
  for (std::size_t i = 0; i < m; ++i) ids[i] = rank[id[from[i]]];
  id.swap(ids);
}

IdentityOrder::IdentityOrder(const ParticleStore& p) {
  if (p.id.empty()) return;
  slot_.resize(p.id.size());
  parallel_for(p.id.size(), [&](std::size_t i) { slot_[p.id[i]] = static_cast<std::uint32_t>(i); });
}

void ParticleStore::set_angular_velocity(std::size_t i, Vec3 w) {
  if (!rotation_enabled_) return;
  wx[i] = w.x; wy[i] = w.y; wz[i] = w.z;
}

bool ParticleStore::same_mass(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& runs) const {
  // Compared as bits, so that reading the one value reproduces every particle's exactly.
  std::size_t first = size();
  for (const auto& [i0, i1] : runs)
    if (i0 < i1) {
      first = i0;
      break;
    }
  if (first == size()) return true;
  auto same = [&](const std::vector<double>& v) {
    const auto one = std::bit_cast<std::uint64_t>(v[first]);
    for (const auto& [i0, i1] : runs)
      if (!std::all_of(v.begin() + i0, v.begin() + i1, [&](double a) { return std::bit_cast<std::uint64_t>(a) == one; }))
        return false;
    return true;
  };
  return same(mass) && same(inv_mass) && (!has_rotation() || same(inv_inertia));
}

void ParticleStore::release_zero_pages(std::size_t first, std::size_t last) {
  for (auto* v : double_arrays(*this)) {
    if (v->size() < last) continue;
    const auto b = v->begin() + static_cast<std::ptrdiff_t>(first), e = v->begin() + static_cast<std::ptrdiff_t>(last);
    if (std::all_of(b, e, [](double a) { return std::bit_cast<std::uint64_t>(a) == 0; })) zero_slots(*v, {{first, last}});
  }
}

void ParticleStore::flag_fixed_from_masses() {
  fixed_flag.clear();
  if (std::none_of(inv_mass.begin(), inv_mass.end(), [](double a) { return a == 0.0; })) return;
  fixed_flag.resize(size());
  for (std::size_t i = 0; i < size(); ++i) fixed_flag[i] = inv_mass[i] == 0.0 ? 1 : 0;
}

void ParticleStore::clear_forces() {
  // Only what is not zero: the slots another process holds stay uncommitted (slot_pages.hpp).
  for (auto* f : {&fx, &fy, &fz}) clear_nonzero(*f);
  if (rotation_enabled_)
    for (auto* t : {&tx, &ty, &tz}) clear_nonzero(*t);
}

}  // namespace cdm
