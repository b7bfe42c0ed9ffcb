/// @file rank_ownership.cpp
/// @brief Which MPI process owns which particle slot (RankSplit), as the slots are read
/// from a checkpoint, reordered, removed and added, and the memory that follows it: the
/// slots of other processes' particles let go of (release_foreign).
#include <algorithm>
#include <cstdint>
#include <vector>

#include "cdm/solver/contact/verlet_list.hpp"
#include "cdm/solver/rank_split.hpp"
#include "cdm/solver/slot_pages.hpp"

namespace cdm {

void RankSplit::hold_rows(ParticleStore& p, const std::vector<std::uint32_t>& from) {
  // Before the permutation: the particle that will be row i is in slot from[i] now.
  const std::size_t n = p.size();
  owner_.resize(n);
  for (int r = 0; r < size_; ++r) {
    const auto [first, last] = row_run(n, r);
    for (std::size_t i = first; i < last; ++i) owner_[from.empty() ? i : from[i]] = static_cast<Owner>(r);
  }
  own_from_owners();
  drop_boundaries();
  release_foreign(p);
  assigned_ = stale_ = held_rows_ = true;
  moving_ = written_ = gathered_ = false;
}

void RankSplit::drop_boundaries() {
  for (auto* slab : {&lower_, &upper_, &top_, &under_}) slab->clear();
  below_ = above_ = -1;
}

void RankSplit::release_foreign(ParticleStore& p) {
  const std::size_t n = p.size();
  std::vector<std::uint8_t> held = owned_;
  held.resize(n, 0);
  for (const auto* ghosts : {&under_, &upper_})
    for (const std::uint32_t i : *ghosts) held[i] = 1;
  const SlotRuns foreign = runs_not_held(n, [&](std::size_t i) { return held[i] != 0; });
  // The positions too: a build reads the own particles' and those their owners send it
  // (RankSplit::prepare_build), or gathers them all.
  for (auto* a : dynamic_arrays(p, true)) zero_slots(*a, foreign);
  // The build positions: the own particles' only (the list holds no ghosts' either).
  if (list_ && list_->listed(n) && !list_->build_positions_own_only()) {
    const SlotRuns others = runs_not_held(n, [&](std::size_t i) { return i < owned_.size() && owned_[i] != 0; });
    for (auto* a : list_->build_position_arrays()) zero_slots(*a, others);
    list_->build_positions_released();
  }
  stale_ = true;
  written_ = gathered_ = false;
}

void RankSplit::own_from_owners() {
  ++ownership_changes_;
  const std::size_t n = owner_.size();
  owned_.assign(n, 0);
  runs_.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    if (owner_[i] != rank_) continue;
    owned_[i] = 1;
    if (!runs_.empty() && runs_.back().second == i) ++runs_.back().second;
    else runs_.push_back({i, i + 1});
  }
}

void RankSplit::permute(const std::vector<std::uint32_t>& from) {
  if (owner_.size() == from.size()) keep(from);  // a reordering keeps every slot
}

void RankSplit::keep(const std::vector<std::uint32_t>& from) {
  if (!assigned_) return;
  const std::size_t n_old = owner_.size();
  std::vector<std::uint32_t> to(n_old, new_particle);
  std::vector<Owner> o(from.size());
  for (std::size_t i = 0; i < from.size(); ++i) {
    o[i] = owner_[from[i]];
    to[from[i]] = static_cast<std::uint32_t>(i);
  }
  owner_.swap(o);
  own_from_owners();
  for (auto* slab : {&lower_, &upper_, &top_, &under_}) {
    std::size_t kept = 0;
    for (const std::uint32_t i : *slab)
      if (to[i] != new_particle) (*slab)[kept++] = to[i];
    slab->resize(kept);
  }
  written_ = false;
}

void RankSplit::added(ParticleStore& p, std::size_t count) {
  if (!assigned_) return;
  const std::size_t n0 = owner_.size();
  owner_.resize(n0 + count, 0);
  if (by_rows_)
    for (int r = 0; r < size_; ++r) {
      const auto [first, last] = row_run(count, r);
      std::fill(owner_.begin() + static_cast<std::ptrdiff_t>(n0 + first),
                owner_.begin() + static_cast<std::ptrdiff_t>(n0 + last), static_cast<Owner>(r));
    }
  own_from_owners();
  if (by_rows_) release_foreign(p);
  written_ = false;
}

void RankSplit::divide_by_rows(ParticleStore& p) {
  by_rows_ = true;
  hold_rows(p, {});
}

}  // namespace cdm
