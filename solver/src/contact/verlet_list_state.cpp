#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/contact/verlet_list.hpp"
#include "cdm/solver/slot_pages.hpp"

// The list follows its particles when they are reordered, removed or added, and goes
// into and out of a checkpoint.

namespace cdm {

void VerletList::save_state(OutArchive& a) const {
  // The contacts only: a listed pair or wall entry out of contact carries nothing (a
  // contact starts afresh), and the pairs are listed again from x0_. A list shared
  // among processes holds its own part only: its whole contacts are held for this (by the
  // process that writes; the others' archives count only).
  // Written as three arrays, field by field, without a copy of the contacts.
  if (a.writes() && rank_split_ && share_ && !holding_ && (!pairs_pending_ || carry_partial_))
    throw std::logic_error("VerletList: a shared list saved without its whole contacts");
  const std::vector<PairContact>* whole = holding_ ? &held_ : pairs_pending_ ? &pair_carry_ : nullptr;
  auto put_field = [&](auto field) {
    if (whole) {
      a.put(static_cast<std::uint64_t>(whole->size()));
      for (const PairContact& c : *whole) a.put(field(c));
      return;
    }
    std::uint64_t n = 0;
    if (history_)
      for (std::size_t k = 0; k < pi_.size(); ++k) n += touch_[k];
    a.put(n);
    if (history_)
      for (std::size_t k = 0; k < pi_.size(); ++k)
        if (touch_[k]) a.put(field(PairContact{pi_[k], pj_[k], hist_[k]}));
  };
  put_field([](const PairContact& c) { return c.i; });
  put_field([](const PairContact& c) { return c.j; });
  put_field([](const PairContact& c) { return c.h; });
  const std::vector<WallContact> wc = holding_walls_ ? held_walls_ : wall_contacts();
  std::vector<std::uint32_t> wi(wc.size()), ww(wc.size());
  std::vector<Vec3> wh(wc.size());
  for (std::size_t k = 0; k < wc.size(); ++k) {
    wi[k] = wc[k].i; ww[k] = wc[k].w; wh[k] = wc[k].h;
  }
  a.put(wi); a.put(ww); a.put(wh);
  // Where each process holds its own particles' build positions only, they stream to
  // the writer as the particles' arrays do.
  a.put_particles(x0_); a.put_particles(y0_); a.put_particles(z0_);
  a.put(static_cast<std::uint8_t>(cut_known_ ? 1 : 0));
  a.put(static_cast<std::uint8_t>(cut_.axis));
  a.put(static_cast<std::uint64_t>(cut_.count));
  for (int k = 0; k < 3; ++k) {
    a.put(cut_.lo[k]);
    a.put(cut_.hi[k]);
  }
  a.put(cut_.range);
  a.put(cut_.width);
}

void VerletList::load_state(InArchive& a, bool built, std::uint64_t builds) {
  // The pair contacts' three arrays are read field by field into the contacts (a
  // large run's would otherwise be held twice); the three must be as long, and fit.
  // Where the processes each read their share (a slot window), each keeps the contacts
  // of the particles i of its window: the first build sends them to their pairs' slabs.
  std::uint64_t nc = 0, again = 0;
  a.get(nc);
  if (nc > a.remaining() / (2 * sizeof(std::uint32_t) + sizeof(Vec3)))
    throw ArchiveError("an array's length (" + std::to_string(nc) + ") does not fit the data that follows");
  const InArchive::SlotWindow& window = a.slot_window();
  std::vector<std::uint32_t> ci(nc);
  a.get_values(ci.data(), ci.size());
  std::size_t kept = 0;
  for (const std::uint32_t i : ci) kept += window.holds(i);
  pair_carry_.resize(kept);
  for (std::size_t k = 0, q = 0; k < nc; ++k)
    if (window.holds(ci[k])) pair_carry_[q++].i = ci[k];
  a.get(again);
  bool ok = again == nc;
  for (std::size_t k = 0, q = 0; ok && k < nc; ++k) {
    std::uint32_t j = 0;
    a.get(j);
    if (window.holds(ci[k])) pair_carry_[q++].j = j;
  }
  if (ok) a.get(again);
  ok = ok && again == nc;
  for (std::size_t k = 0, q = 0; ok && k < nc; ++k) {
    Vec3 h;
    a.get(h);
    if (window.holds(ci[k])) pair_carry_[q++].h = h;
  }
  std::vector<std::uint32_t>().swap(ci);
  if (!ok) throw ArchiveError("the contact list is inconsistent");
  std::vector<std::uint32_t> wi, ww;
  std::vector<Vec3> wh;
  a.get(wi); a.get(ww); a.get(wh);
  // The build positions likewise: each process reads its window's (its rows').
  for (auto* v : {&x0_, &y0_, &z0_}) get_slots(a, *v);
  own_only_ = window.set && x0_.size() == window.n;
  walls_own_only_ = false;
  std::uint8_t known = 0, axis = 0;
  std::uint64_t count = 0;
  a.get(known); a.get(axis); a.get(count);
  Slabs cut;
  for (int k = 0; k < 3; ++k) {
    a.get(cut.lo[k]);
    a.get(cut.hi[k]);
  }
  a.get(cut.range); a.get(cut.width);
  cut.axis = axis;
  cut.count = count;
  const std::size_t n = x0_.size();
  ok = y0_.size() == n && z0_.size() == n;
  // The slabs, as a build cuts them: at most 4096 along one axis, of a finite width;
  // along a periodic axis an even number, at least four, that wrap.
  ok = ok && known <= 1 && axis < 3 && count >= 1 && count <= 4096 && std::isfinite(cut.width) && cut.width > 0.0 &&
       std::isfinite(cut.lo[axis]);
  cut.wrap = ok && count > 1 && box_.on[axis];
  ok = ok && (!cut.wrap || (count >= 4 && count % 2 == 0));
  // Contacts of particles listed, each pair once (in list order), and the wall
  // contacts in strictly increasing (i, w) order.
  ok = ok && (history_ || nc == 0);
  for (std::size_t k = 0; ok && k < pair_carry_.size(); ++k)
    ok = pair_carry_[k].i != pair_carry_[k].j && pair_carry_[k].i < n && pair_carry_[k].j < n;
  ok = ok && ww.size() == wi.size() && wh.size() == wi.size() && (history_ || wi.empty());
  for (std::size_t k = 0; ok && k < wi.size(); ++k)
    ok = wi[k] < n && ww[k] < walls_.size() && (k == 0 || wall_key(wi[k - 1], ww[k - 1]) < wall_key(wi[k], ww[k]));
  if (!ok) throw ArchiveError("the contact list is inconsistent");
  // Kept in (i, j) order: the build that lists the pairs again finds each particle's
  // contacts by their row, without a copy.
  std::sort(pair_carry_.begin(), pair_carry_.end(), PairContact::by_key);
  for (std::size_t k = 1; k < pair_carry_.size(); ++k)
    if (pair_carry_[k - 1].key() == pair_carry_[k].key()) throw ArchiveError("the contact list is inconsistent");
  carry_sorted_ = true;
  carry_partial_ = window.set;
  pairs_pending_ = true;
  for (auto* v : {&pi_, &pj_, &slab_start_}) v->clear();
  hist_.clear();
  touch_.clear();
  wall_carry_.resize(wi.size());
  for (std::size_t k = 0; k < wi.size(); ++k) wall_carry_[k] = {wi[k], ww[k], wh[k]};
  drop_wall_entries();
  built_ = built;
  builds_ = builds;
  cut_ = cut;
  cut_known_ = known != 0;
  displacement_ = -1.0;
  drift_bound_ = std::numeric_limits<double>::infinity();  // the moves since the build are unknown
  wall_candidates_stale_ = true;  // listed from the build's positions at the next update
}

void VerletList::renumber_pair_carry(const std::vector<std::uint32_t>& to) {
  // As permute and remap renumber listed pairs: each pair stays (i, j) as its build
  // listed it (key_order), whatever the slots, the history seen from i.
  std::erase_if(pair_carry_, [&](const PairContact& c) {
    return c.j >= to.size() || to[c.i] == new_particle || to[c.j] == new_particle;
  });
  for (PairContact& c : pair_carry_) {
    c.i = to[c.i];
    c.j = to[c.j];
  }
  std::sort(pair_carry_.begin(), pair_carry_.end(), PairContact::by_key);
  carry_sorted_ = true;
}

void VerletList::permute(const std::vector<std::uint32_t>& from) {
  const std::size_t n = from.size();
  if (x0_.size() != n) return;  // nothing listed yet: the next evaluation builds
  std::vector<std::uint32_t> to(n);
  for (std::size_t i = 0; i < n; ++i) to[from[i]] = static_cast<std::uint32_t>(i);
  // Each pair keeps its particles in the order its build listed them (key_order), which
  // a new order of the slots does not change, and so its history.
  for (std::size_t k = 0; k < pi_.size(); ++k) {
    pi_[k] = to[pi_[k]];
    pj_[k] = to[pj_[k]];
  }
  if (pairs_pending_) renumber_pair_carry(to);
  set_aside_wall_history(&to);
  follow_build_positions(from);
}

void VerletList::follow_build_positions(const std::vector<std::uint32_t>& from) {
  std::vector<double> tmp;
  for (auto* v : {&x0_, &y0_, &z0_}) permute_array(*v, from, tmp);
  wall_candidates_stale_ = true;  // listed again, in the new order, from x0_
}

void VerletList::remap(const std::vector<std::uint32_t>& from, const ParticleStore& p) {
  const std::size_t n_old = x0_.size(), n = from.size();
  std::vector<std::uint32_t> to(n_old, new_particle);
  for (std::size_t i = 0; i < n; ++i)
    if (from[i] != new_particle && from[i] < n_old) to[from[i]] = static_cast<std::uint32_t>(i);
  // Pairs of two particles left keep their slab (each particle stays where it was) and
  // their history, as their build listed them (as permute keeps them); the slab starts
  // count the pairs kept.
  std::size_t kept = 0;
  for (std::size_t s = 0; s + 1 < slab_start_.size(); ++s) {
    const std::size_t begin = slab_start_[s], end = slab_start_[s + 1];
    slab_start_[s] = static_cast<std::uint32_t>(kept);
    for (std::size_t k = begin; k < end; ++k) {
      const std::uint32_t i = pi_[k] < n_old ? to[pi_[k]] : new_particle, j = pj_[k] < n_old ? to[pj_[k]] : new_particle;
      if (i == new_particle || j == new_particle) continue;
      pi_[kept] = i;
      pj_[kept] = j;
      if (history_) {
        hist_[kept] = hist_[k];
        touch_[kept] = touch_[k];
      }
      ++kept;
    }
  }
  if (!slab_start_.empty()) slab_start_.back() = static_cast<std::uint32_t>(kept);
  pi_.resize(kept);
  pj_.resize(kept);
  if (history_) {
    hist_.resize(kept);
    touch_.resize(kept);
  }
  // The contacts of the particles left follow them; new particles have none.
  if (pairs_pending_) renumber_pair_carry(to);
  set_aside_wall_history(&to);
  // Particles removed only, in order, from a built list: the pairs kept are those a
  // listing from the build positions left finds (each pair's listing depends on its two
  // particles alone), in the same order (the slots keep their order, the pairs their
  // slabs, cut_). So the list stays built: the others keep their build positions, and
  // the drift bound holds for them.
  bool removed_only = built_ && n <= n_old;
  for (std::size_t i = 0; removed_only && i < n; ++i)
    removed_only = from[i] < n_old && (i == 0 || from[i] > from[i - 1]);
  if (removed_only) {
    follow_build_positions(from);
    return;
  }
  // Build positions: the particles' own (a new particle's is where it appeared); the
  // list is built again at the next update, so the new particles find their partners.
  // Among processes the slots whose positions a process does not hold read zero in
  // both: their pages stay uncommitted.
  copy_changed(x0_, p.x);
  copy_changed(y0_, p.y);
  copy_changed(z0_, p.z);
  own_only_ = false;
  built_ = false;
  wall_candidates_stale_ = true;
}

}  // namespace cdm
