// The Verlet list's particle–wall candidates and the history beside them.
#include "cdm/solver/contact/verlet_list.hpp"

#include <algorithm>
#include <stdexcept>

namespace cdm {

void VerletList::list_wall_candidates(const ParticleStore& p, const SearchPoints* at) {
  // From the positions at the last build (@p at, or x0_) and the walls where they stand
  // now. A particle moves less than skin/2 before the next build, so one farther
  // than r + skin from a wall cannot reach it: each particle is listed with the walls it
  // may touch. A wall not perpendicular to every periodic axis sees wrapped particles
  // jump, so then every particle is listed with every wall. Where x0_ holds the own
  // particles' only, only they are listed (a process resolves its own particles' walls).
  // At a build divided among processes that already own their particles, those it owned
  // (whose rows it sends as they change process) and those of its new slabs (whose rows
  // it receives): among P processes about 2/P of the particles, not all of them.
  const std::size_t n = x0_.size(), nw = walls_.size();
  const std::uint8_t* const own = !at && own_only_ && share_ ? share_->own_slots() : nullptr;
  if (!at && own_only_ && !own) throw std::logic_error("VerletList: build positions held in part, without owners");
  const double* const X0 = at ? at->x : x0_.data();
  const double* const Y0 = at ? at->y : y0_.data();
  const double* const Z0 = at ? at->z : z0_.data();
  const std::uint8_t* const owned = at && share_ && !rank_slab_first_.empty() ? share_->own_slots() : nullptr;
  const SlabOf slab_of = owned ? slab_map(cut_, *at) : SlabOf{};
  const std::uint32_t s0 = owned ? rank_slab_first_[static_cast<std::size_t>(share_->share_rank())] : 0,
                      s1 = owned ? rank_slab_first_[static_cast<std::size_t>(share_->share_rank()) + 1] : 0;
  // At a held build (prepare_held_build) the positions of the particles entering this
  // process's slabs are in x0_ only (bit 1 of held: the process's after the build).
  const std::uint8_t* const held = at && held_build_.ready ? held_build_.held.data() : nullptr;
  auto listed = [&](std::size_t i) {
    if (own) return own[i] != 0;
    if (!owned || owned[i]) return true;
    if (held) return (held[i] & 2) != 0;
    const std::uint32_t s = slab_of(static_cast<std::uint32_t>(i));
    return s >= s0 && s < s1;
  };
  walls_own_only_ = (own != nullptr || owned != nullptr) && nw > 0;
  if (!wall_carry_pending_) set_aside_wall_history(nullptr);
  wall_begin_.assign(1, 0);
  wall_candidates_stale_ = false;
  listed_time_ = time_;
  // Likewise a surface of revolution, or a plane that turns, with any periodic axis.
  bool filter = skin_ >= 0.0;
  for (const Wall& w : walls_) {
    const double nrm[3] = {w.normal.x, w.normal.y, w.normal.z};
    const bool fixed_plane = w.shape == WallShape::plane && w.motion.kind != WallMotion::Kind::rotation;
    for (int a = 0; a < 3; ++a)
      if (box_.on[a] && (nrm[a] != 0.0 || !fixed_plane)) filter = false;
  }
  // A listed entry takes its history from the carried contact of the same particle and
  // wall (both in (i, w) order); a contact not listed again has ended.
  auto carry = wall_carry_.cbegin();
  const auto carry_end = wall_carry_.cend();
  for (std::size_t i = 0; i < n && nw; ++i) {
    if (!listed(i)) continue;
    const std::size_t before = wall_ids_.size();
    const Vec3 X = held && (held[i] & 2) ? Vec3{x0_[i], y0_[i], z0_[i]} : Vec3{X0[i], Y0[i], Z0[i]};
    const double r = held ? held_build_.radius(p, i) : p.radius[i];
    for (std::size_t w = 0; w < nw; ++w) {
      const Wall& wall = posed_[w];
      const double reach = wall.shape == WallShape::plane ? wall.distance(X) : wall.reach_distance(X);
      if (filter && !(reach < r + skin_)) continue;
      wall_ids_.push_back(static_cast<std::uint32_t>(w));
      if (!history_) continue;
      const std::uint64_t key = wall_key(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(w));
      while (carry != carry_end && carry->key() < key) ++carry;
      const bool carried = carry != carry_end && carry->key() == key;
      wall_hist_.push_back(carried ? carry->h : Vec3{});
      wall_touch_.push_back(carried ? 1 : 0);
    }
    if (wall_ids_.size() != before) {
      wall_candidates_.push_back(static_cast<std::uint32_t>(i));
      wall_begin_.push_back(static_cast<std::uint32_t>(wall_ids_.size()));
    }
  }
  std::vector<WallContact>().swap(wall_carry_);
  wall_carry_pending_ = false;
}

std::vector<VerletList::WallContact> VerletList::wall_contacts() const {
  if (wall_carry_pending_) return wall_carry_;
  std::vector<WallContact> out;
  if (!history_) return out;
  for (std::size_t c = 0; c < wall_candidates_.size(); ++c)
    for (std::uint32_t q = wall_begin_[c]; q < wall_begin_[c + 1]; ++q)
      if (wall_touch_[q]) out.push_back({wall_candidates_[c], wall_ids_[q], wall_hist_[q]});
  return out;
}

void VerletList::set_aside_wall_history(const std::vector<std::uint32_t>* to) {
  wall_carry_ = wall_contacts();
  if (to) {
    std::erase_if(wall_carry_, [&](const WallContact& c) { return c.i >= to->size() || (*to)[c.i] == new_particle; });
    for (WallContact& c : wall_carry_) c.i = (*to)[c.i];
    std::sort(wall_carry_.begin(), wall_carry_.end(), WallContact::by_key);
  }
  drop_wall_entries();
}

void VerletList::drop_wall_entries() {
  wall_carry_pending_ = true;
  for (auto* v : {&wall_candidates_, &wall_begin_, &wall_ids_}) v->clear();
  wall_hist_.clear();
  wall_touch_.clear();
}

std::pair<std::uint32_t, std::uint32_t> VerletList::wall_entries(std::uint32_t i) const {
  const auto c = std::lower_bound(wall_candidates_.begin(), wall_candidates_.end(), i);
  if (c == wall_candidates_.end() || *c != i) return {0, 0};
  const auto k = static_cast<std::size_t>(c - wall_candidates_.begin());
  return {wall_begin_[k], wall_begin_[k + 1]};
}

}  // namespace cdm
