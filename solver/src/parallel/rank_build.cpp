/// @file rank_build.cpp
/// @brief What a Verlet-list build moves among the MPI processes (RankSplit): the
/// positions it reads, before it, and the particles whose slabs it dealt to another
/// process, after it (assign()).
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "cdm/solver/contact/verlet_list.hpp"
#include "cdm/solver/rank_split.hpp"

namespace cdm {

bool RankSplit::holds_build(const ParticleStore& p) {
  // Every particle must have an owner that holds its current state: not before the
  // processes hold their rows (hold_rows); and nothing to do where every process holds
  // the whole state anyway.
  const bool whole = !stale_ || moving_ || !assigned_ || owner_.size() != p.size() || p.size() == 0;
  return !any(whole);
}

void RankSplit::prepare_build(ParticleStore& p, VerletList& list) {
  // The ghosts' positions now: the carried contacts' pairs reach into them.
  exchange_ghosts(p);
  list.prepare_held_build(p);
  moving_ = held_build_ = true;
}

void RankSplit::assign(VerletList& list, ParticleStore& p) {
  const std::size_t n = p.size(), nslab = list.slab_count();
  // The slabs as the build dealt them out (VerletList::divide).
  slab_first_ = list.rank_slab_first();
  if (slab_first_.size() != static_cast<std::size_t>(size_) + 1)
    throw std::logic_error("RankSplit: the list was not built shared among the ranks");
  const auto size = static_cast<std::size_t>(size_);
  slab_owner_.assign(nslab, 0);
  for (std::size_t r = 0; r < size; ++r)
    for (std::size_t s = slab_first_[r]; s < slab_first_[r + 1]; ++s) slab_owner_[s] = static_cast<int>(r);
  // Where only the positions were gathered, or a restart read each rank's rows, each
  // particle's state is its old owner's.
  std::vector<Owner> before;
  if (moving_ || held_rows_) {
    if (owner_.size() != n) throw std::logic_error("RankSplit: particles changed while their owners change");
    before.swap(owner_);
  }
  // Each particle's slab: at a held build (prepare_build) its owner alone has its
  // position, so each process finds its own particles' new owners and tells the others
  // of those that change; else every process has every position.
  std::vector<std::uint32_t> slab_of;
  if (held_build_) new_owners(list, p, before);
  else {
    slab_of = list.particle_slabs(p);
    owner_.resize(n);
    for (std::size_t i = 0; i < n; ++i) owner_[i] = static_cast<Owner>(slab_owner_[slab_of[i]]);
  }
  own_from_owners();
  const std::uint32_t s0 = slab_first_[static_cast<std::size_t>(rank_)], s1 = slab_first_[static_cast<std::size_t>(rank_) + 1];
  drop_boundaries();
  // The slabs either side of the rank's run, another rank's: below its first (the last
  // slab below slab 0 where the slabs wrap) and after its last (slab 0 after the last).
  // Where they wrap the slab count is even, so a slab's parity is that of its place.
  const bool wrap = list.slabs_wrap();
  const std::size_t sb = s0 > 0 ? s0 - 1 : wrap ? nslab - 1 : nslab, sa = s1 < nslab ? s1 : wrap ? 0 : nslab;
  if (s0 < s1 && sb < nslab && slab_owner_[sb] != rank_) below_ = slab_owner_[sb];
  if (s0 < s1 && sa < nslab && slab_owner_[sa] != rank_) above_ = slab_owner_[sa];
  lower_odd_ = (s0 & 1) != 0;
  upper_odd_ = (s1 & 1) != 0;
  if (held_build_) boundaries_from_neighbours(list, s0, s1);
  else if (below_ >= 0 || above_ >= 0)  // one pass over the particles for the four boundary slabs
    for (std::size_t i = 0; i < n; ++i) {
      const auto k = static_cast<std::uint32_t>(i);
      if (below_ >= 0 && slab_of[i] == s0) lower_.push_back(k);
      if (below_ >= 0 && slab_of[i] == sb) under_.push_back(k);
      if (above_ >= 0 && slab_of[i] == sa) upper_.push_back(k);
      if (above_ >= 0 && slab_of[i] == s1 - 1) top_.push_back(k);
    }
  list.set_rank_slabs(s0, s1);
  list_ = &list;
  assigned_ = true;
  builds_ = list.builds();
  moving_ = written_ = held_rows_ = held_build_ = false;
  if (!before.empty()) {
    stale_ = true;
    migrate(p, list, before);
    exchange_ghosts(p, true);
  }
  release_foreign(p);
}

void RankSplit::new_owners(const VerletList& list, const ParticleStore& p, const std::vector<Owner>& before) {
  // This process's particles' positions are those the list was built from, or where it
  // listed a loaded list's pairs again, their build positions (which it holds for its rows).
  const std::size_t n = before.size();
  const SearchPoints built{list.build_positions(0), list.build_positions(1), list.build_positions(2), nullptr, n};
  const SearchPoints at = list.build_positions_own_only() ? SearchPoints::of(p) : built;
  const VerletList::SlabOf slab = VerletList::slab_map(list.cut(), at);
  owner_ = before;
  std::vector<std::uint32_t> moves;  // (slot, new owner) of this process's particles
  for (std::size_t i = 0; i < n; ++i) {
    if (before[i] != rank_) continue;
    const int to = slab_owner_[slab(static_cast<std::uint32_t>(i))];
    if (to == rank_) continue;
    moves.insert(moves.end(), {static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(to)});
    owner_[i] = static_cast<Owner>(to);
  }
  std::vector<std::vector<std::uint32_t>> out(static_cast<std::size_t>(size_), moves);
  out[static_cast<std::size_t>(rank_)].clear();
  const std::vector<std::uint32_t> in = swap_values(out);
  for (std::size_t k = 0; k + 1 < in.size(); k += 2) owner_[in[k]] = static_cast<Owner>(in[k + 1]);
}

void RankSplit::boundaries_from_neighbours(const VerletList& list, std::uint32_t s0, std::uint32_t s1) {
  // This process's first and last slabs' particles, from their build positions (which it
  // holds for its own particles), in slot order; the ghost slabs are the neighbours'
  // (the rank below's last slab, the rank above's first), which they send. Each message
  // names what it carries: two ranks may be each other's neighbours both ways.
  const std::size_t n = owner_.size();
  const SearchPoints at{list.build_positions(0), list.build_positions(1), list.build_positions(2), nullptr, n};
  const VerletList::SlabOf slab = VerletList::slab_map(list.cut(), at);
  for (std::size_t i = 0; i < n; ++i) {
    if (owner_[i] != rank_) continue;
    const std::uint32_t s = slab(static_cast<std::uint32_t>(i));
    if (below_ >= 0 && s == s0) lower_.push_back(static_cast<std::uint32_t>(i));
    if (above_ >= 0 && s == s1 - 1) top_.push_back(static_cast<std::uint32_t>(i));
  }
  enum : std::uint32_t { first_slab = 0, last_slab = 1 };
  std::vector<std::vector<std::uint32_t>> out(static_cast<std::size_t>(size_));
  auto send = [&](int to, std::uint32_t what, const std::vector<std::uint32_t>& slots) {
    std::vector<std::uint32_t>& o = out[static_cast<std::size_t>(to)];
    o.insert(o.end(), {what, static_cast<std::uint32_t>(slots.size())});
    o.insert(o.end(), slots.begin(), slots.end());
  };
  if (below_ >= 0) send(below_, first_slab, lower_);
  if (above_ >= 0) send(above_, last_slab, top_);
  const std::vector<std::uint32_t> in = swap_values(out);
  for (std::size_t k = 0; k + 2 <= in.size();) {
    std::vector<std::uint32_t>& to = in[k] == first_slab ? upper_ : under_;
    const std::size_t m = in[k + 1];
    to.insert(to.end(), in.begin() + static_cast<std::ptrdiff_t>(k + 2), in.begin() + static_cast<std::ptrdiff_t>(k + 2 + m));
    k += 2 + m;
  }
}

}  // namespace cdm
