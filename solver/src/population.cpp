#include "cdm/solver/population.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "cdm/solver/parallel.hpp"
#include "cdm/solver/placement.hpp"

namespace cdm {

namespace {

/// The last insertion event reached at time @p t: k for start + k·interval (interval > 0).
std::uint64_t event_index(const InsertionSpec& in, double t) {
  // Clamped: a tiny interval (many events per step) must not overflow the count.
  return static_cast<std::uint64_t>(std::clamp(std::floor((t - in.start) / in.interval + 1e-9), 0.0, 0x1p62));
}

}  // namespace

Population::Population(const SceneSpec& spec)
    : spec_(spec), inserted_(spec.insertions.size()), removed_(spec.outlets.size()) {
  for (const auto& in : spec.insertions) feeds_.push_back({std::mt19937_64(in.seed), 0, false});
}

bool Population::any_leaving(const ParticleStore& p, std::size_t i0, std::size_t i1) const {
  if (spec_.outlets.empty()) return false;
  const auto none = static_cast<std::uint32_t>(spec_.outlets.size());
  return parallel_max(i1 - i0, [&](std::size_t k) { return outlet_of(p.position(i0 + k)) != none ? 1.0 : 0.0; }) != 0.0;
}

std::vector<Population::Leaving> Population::leaving(const ParticleStore& p, std::size_t i0, std::size_t i1) const {
  std::vector<Leaving> out;
  const auto none = static_cast<std::uint32_t>(spec_.outlets.size());
  for (std::size_t i = i0; i < i1; ++i)
    if (const std::uint32_t o = outlet_of(p.position(i)); o != none)
      out.push_back({static_cast<std::uint32_t>(i), o, p.mass[i]});
  return out;
}

std::vector<std::uint32_t> Population::remove(ParticleStore& p, const std::vector<Leaving>& gone) {
  std::vector<std::uint32_t> from;
  from.reserve(p.size() - std::min(p.size(), gone.size()));
  std::size_t g = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (g == gone.size() || gone[g].slot != i) {
      from.push_back(static_cast<std::uint32_t>(i));
      continue;
    }
    Tally& t = removed_[gone[g].outlet];
    ++t.count;
    t.mass += gone[g++].mass;
  }
  if (g != gone.size()) throw std::logic_error("Population::remove: the slots removed are not in order");
  p.keep(from);
  return from;
}

bool Population::insertion_due(double t) const {
  for (std::size_t k = 0; k < feeds_.size(); ++k) {
    const InsertionSpec& in = spec_.insertions[k];
    const Feed& f = feeds_[k];
    if (f.done || t < in.start * (1.0 - 1e-12)) continue;
    // At every step: due when a particle is owed (an event owing none does nothing).
    if (in.interval <= 0.0) {
      if (owed(k, t)) return true;
      continue;
    }
    const std::uint64_t e = event_index(in, t);
    if (e >= f.next_event) return true;
  }
  return false;
}

bool Population::total_left_of(std::size_t k) const {
  const InsertionSpec& in = spec_.insertions[k];
  const Tally& done = inserted_[k];
  return in.total_by_mass ? done.mass < in.total : static_cast<double>(done.count) < in.total;
}

bool Population::owed(std::size_t k, double t) const {
  // What is still due at time t, in the rate's and the total's measures.
  const InsertionSpec& in = spec_.insertions[k];
  const Tally& done = inserted_[k];
  const double target = in.rate * std::max(0.0, std::min(t, in.end) - in.start);
  const bool rate_left =
      in.rate_by_mass ? done.mass < target : static_cast<double>(done.count) < std::floor(target + 1e-9);
  return rate_left && total_left_of(k);
}

std::size_t Population::insert(ParticleStore& p, double t, Vec3 g, const std::vector<std::uint32_t>* near) {
  const std::size_t n_before = p.size();
  std::size_t added = 0;
  for (std::size_t k = 0; k < feeds_.size(); ++k) {
    const InsertionSpec& in = spec_.insertions[k];
    Feed& f = feeds_[k];
    if (f.done || t < in.start * (1.0 - 1e-12)) continue;
    if (in.interval > 0.0) {
      const std::uint64_t e = event_index(in, t);
      if (e < f.next_event) continue;
      f.next_event = e + 1;
    }
    added += run_event(k, p, t, g, near, n_before);
  }
  return added;
}

double Population::reach_radius(const ParticleStore& p) const {
  double r_max = 0.0;
  for (double r : p.radius) r_max = std::max(r_max, r);
  for (const InsertionSpec& in : spec_.insertions) r_max = std::max(r_max, in.size.largest());
  return r_max;
}

bool Population::near_box(std::size_t k, Vec3 x, double r_max) const {
  const InsertionSpec& in = spec_.insertions[k];
  const double reach = in.size.largest() + r_max;
  const Vec3 mid = 0.5 * (in.region.lower + in.region.upper), half = 0.5 * (in.region.upper - in.region.lower);
  const Vec3 d = spec_.periodic.min_image(x - mid);
  return std::abs(d.x) <= half.x + reach && std::abs(d.y) <= half.y + reach && std::abs(d.z) <= half.z + reach;
}

bool Population::near_insertion(Vec3 x, double r_max) const {
  for (std::size_t k = 0; k < feeds_.size(); ++k)
    if (!feeds_[k].done && near_box(k, x, r_max)) return true;
  return false;
}

std::size_t Population::run_event(std::size_t k, ParticleStore& p, double t, Vec3 g,
                                  const std::vector<std::uint32_t>* near, std::size_t n_before) {
  const InsertionSpec& in = spec_.insertions[k];
  Feed& f = feeds_[k];
  Tally& done = inserted_[k];
  const Material& mat = spec_.materials[in.material];
  auto total_left = [&] { return total_left_of(k); };
  auto wanted = [&] { return owed(k, t); };
  // At or after `end`, the last event: it inserts what the rate owes up to `end`.
  if (!(t < in.end) || !total_left()) f.done = true;
  if (!wanted()) return 0;
  // The particles near the box (near_box), which a new one must clear.
  double r_max = in.size.largest();
  for (double r : p.radius) r_max = std::max(r_max, r);
  SequentialPlacement placed(r_max, spec_.walls, spec_.meshes, t, spec_.periodic);
  auto consider = [&](std::size_t i) {
    if (near_box(k, p.position(i), r_max)) placed.add(p.position(i), p.radius[i]);
  };
  if (near) {
    for (std::uint32_t i : *near) consider(i);
    for (std::size_t i = n_before; i < p.size(); ++i) consider(i);
  } else {
    for (std::size_t i = 0; i < p.size(); ++i) consider(i);
  }
  constexpr int max_tries = 1000;
  std::size_t added = 0;
  while (wanted()) {
    const double r = in.size.sample(f.rng);
    bool ok = false;
    Vec3 x;
    for (int tries = 0; tries < max_tries && !ok; ++tries) {
      const double a = uniform01(f.rng), b = uniform01(f.rng), c = uniform01(f.rng);
      x = in.region.draw(a, b, c);
      ok = placed.clear(x, r);
    }
    if (!ok) {
      ++jammed_;
      f.done = !total_left();  // what is left is due at the next event
      break;
    }
    placed.add(x, r);
    p.add(x, in.velocity, r, mat.density, in.material);
    const std::size_t i = p.size() - 1;
    p.fx[i] = p.mass[i] * g.x; p.fy[i] = p.mass[i] * g.y; p.fz[i] = p.mass[i] * g.z;
    ++done.count;
    done.mass += p.mass[i];
    ++added;
  }
  if (!total_left()) f.done = true;
  return added;
}

void Population::save_state(OutArchive& a) const {
  a.put(static_cast<std::uint64_t>(feeds_.size()));
  for (std::size_t k = 0; k < feeds_.size(); ++k) {
    std::ostringstream os;
    os << feeds_[k].rng;
    a.put(os.str());
    a.put(feeds_[k].next_event);
    a.put(static_cast<std::uint8_t>(feeds_[k].done));
    a.put(inserted_[k].count);
    a.put(inserted_[k].mass);
  }
  a.put(static_cast<std::uint64_t>(removed_.size()));
  for (const Tally& r : removed_) {
    a.put(r.count);
    a.put(r.mass);
  }
  a.put(jammed_);
}

void Population::load_state(InArchive& a) {
  std::uint64_t nf = 0;
  a.get(nf);
  if (nf != feeds_.size()) throw ArchiveError("its insertions differ from the scene's");
  for (std::size_t k = 0; k < feeds_.size(); ++k) {
    std::string state;
    a.get(state);
    std::istringstream is(state);
    is >> feeds_[k].rng;
    if (!is) throw ArchiveError("the random state of " + spec_.insertions[k].key + " is corrupted");
    std::uint8_t done = 0;
    a.get(feeds_[k].next_event);
    a.get(done);
    a.get(inserted_[k].count);
    a.get(inserted_[k].mass);
    if (done > 1 || !std::isfinite(inserted_[k].mass)) throw ArchiveError("the state of " + spec_.insertions[k].key + " is corrupted");
    feeds_[k].done = done != 0;
  }
  std::uint64_t no = 0;
  a.get(no);
  if (no != removed_.size()) throw ArchiveError("its outlets differ from the scene's");
  for (Tally& r : removed_) {
    a.get(r.count);
    a.get(r.mass);
    if (!std::isfinite(r.mass)) throw ArchiveError("its outlet record is corrupted");
  }
  a.get(jammed_);
}

}  // namespace cdm
