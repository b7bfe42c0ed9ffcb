#include "cdm/solver/contact/mesh_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "cdm/solver/parallel.hpp"

namespace cdm {

namespace {
/// Two closest points this close, relative to the radius, are the same point seen from two
/// triangles (rounding moves a closest point by ~1e-16 of the coordinates; where two
/// triangles' distances tie to rounding their closest points may lie ~1e-8 d apart, the
/// distance being flat to second order at its minimum).
constexpr double same = 1e-7;
/// Largest number of grid cells (4 Mi: 16 MiB of cell starts).
constexpr double max_cells = 4.0 * 1024 * 1024;
/// range(i0, i1, out) appends what particles [@p first, @p last) give to @p out; with
/// @p threads each thread takes its share of the particles (thread_range, as the
/// integrator's pass) into its own buffer, and the buffers are joined in thread order,
/// which is particle order: the result is the one a single thread makes.
template <class T, class Range>
void in_particle_order(std::size_t first, std::size_t last, bool threads, Range& range, std::vector<T>& out) {
  if (!threads) {
    range(first, last, out);
    return;
  }
  std::vector<std::vector<T>> part;
#pragma omp parallel
  {
#pragma omp single
    part.resize(thread_id().second);
    const auto [i0, i1] = thread_range(last - first);
    range(first + i0, first + i1, part[thread_id().first]);
  }
  for (auto& v : part) out.insert(out.end(), v.begin(), v.end());
}

}  // namespace

MeshContacts::MeshContacts(std::vector<TriangleMesh> meshes) : meshes_(std::move(meshes)) {
  std::uint32_t v0 = 0, e0 = 0;
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const TriangleMesh& mesh = meshes_[m];
    for (std::size_t t = 0; t < mesh.size(); ++t) {
      corner_.push_back({mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2)});
      normal_.push_back(mesh.normals[t]);
      std::array<std::uint32_t, 3> v = mesh.triangles[t], e = mesh.edges[t];
      for (auto& x : v) x += v0;
      for (auto& x : e) x += e0;
      tri_v_.push_back(v);
      tri_e_.push_back(e);
      tri_mesh_.push_back(static_cast<std::uint32_t>(m));
    }
    v0 += static_cast<std::uint32_t>(mesh.vertices.size());
    e0 += mesh.edge_count;
    // The inverse motion: the same motion run backwards.
    WallMotion inv = mesh.motion;
    inv.velocity = -inv.velocity;
    inv.amplitude = -inv.amplitude;
    inv.angular_velocity = -inv.angular_velocity;
    double far = 0.0;
    if (mesh.motion.kind == WallMotion::Kind::rotation)
      for (const Vec3& v : mesh.vertices) {
        const Vec3 d = v - mesh.motion.origin;
        far = std::max(far, norm(d - dot(d, mesh.motion.axis) * mesh.motion.axis));
      }
    moves_.push_back(mesh.motion.moving() ? 1 : 0);
    inverse_.push_back(inv);
    axis_reach_.push_back(far);
    any_moves_ = any_moves_ || mesh.motion.moving();
  }
}

void MeshContacts::build_grid(double reach) {
  reach_ = reach;
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const auto& c : corner_)
    for (const Vec3& v : c) {
      lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
      hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    }
  // Cells of edge h over the box grown by the reach and a cell: about 8 cells per
  // triangle (a few triangles per cell near the surface), no smaller than half the reach,
  // and at most max_cells in all.
  const Vec3 ext = hi - lo;
  const double big = std::max({ext.x, ext.y, ext.z});
  const double target = std::clamp(8.0 * static_cast<double>(corner_.size()), 4096.0, max_cells);
  double h = std::max(0.5 * reach, big / 4096.0);
  auto count = [&](double e) { return std::floor((e + 2.0 * (reach + h)) / h) + 1.0; };
  const double vol = (ext.x + 2 * reach) * (ext.y + 2 * reach) * (ext.z + 2 * reach);
  h = std::max(h, std::cbrt(vol / target));
  if (!(h > 0.0)) h = 1.0;  // a single point and no reach: any cell
  while (count(ext.x) * count(ext.y) * count(ext.z) > max_cells) h *= 1.25;
  h_ = h;
  lo_ = lo - Vec3{reach + h, reach + h, reach + h};
  nx_ = static_cast<long>(std::floor((ext.x + 2.0 * (reach + h)) / h)) + 1;
  ny_ = static_cast<long>(std::floor((ext.y + 2.0 * (reach + h)) / h)) + 1;
  nz_ = static_cast<long>(std::floor((ext.z + 2.0 * (reach + h)) / h)) + 1;
  const std::size_t ncell = static_cast<std::size_t>(nx_ * ny_ * nz_);
  // A cell lists a triangle when the triangle comes within reach of some point of the
  // cell: within reach + the half diagonal of the cell's centre.
  const double within = reach + 0.5 * std::sqrt(3.0) * h;
  auto visit = [&](auto&& add) {
    for (std::uint32_t t = 0; t < corner_.size(); ++t) {
      const auto& c = corner_[t];
      Vec3 a = c[0], b = c[0];
      for (const Vec3& v : c) {
        a = {std::min(a.x, v.x), std::min(a.y, v.y), std::min(a.z, v.z)};
        b = {std::max(b.x, v.x), std::max(b.y, v.y), std::max(b.z, v.z)};
      }
      auto cell = [&](double x, double l) { return static_cast<long>(std::floor((x - l) / h)); };
      const long x0 = std::max(0L, cell(a.x - within, lo_.x)), x1 = std::min(nx_ - 1, cell(b.x + within, lo_.x));
      const long y0 = std::max(0L, cell(a.y - within, lo_.y)), y1 = std::min(ny_ - 1, cell(b.y + within, lo_.y));
      const long z0 = std::max(0L, cell(a.z - within, lo_.z)), z1 = std::min(nz_ - 1, cell(b.z + within, lo_.z));
      for (long iz = z0; iz <= z1; ++iz)
        for (long iy = y0; iy <= y1; ++iy)
          for (long ix = x0; ix <= x1; ++ix) {
            const Vec3 centre = lo_ + Vec3{(static_cast<double>(ix) + 0.5) * h, (static_cast<double>(iy) + 0.5) * h,
                                           (static_cast<double>(iz) + 0.5) * h};
            const Vec3 q = closest_point_on_triangle(centre, c[0], c[1], c[2]).point;
            if (dot(q - centre, q - centre) <= within * within)
              add(static_cast<std::size_t>((iz * ny_ + iy) * nx_ + ix), t);
          }
    }
  };
  cell_start_.assign(ncell + 1, 0);
  visit([&](std::size_t cell, std::uint32_t) { ++cell_start_[cell + 1]; });
  for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_tris_.assign(cell_start_[ncell], 0);
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  visit([&](std::size_t cell, std::uint32_t t) { cell_tris_[fill[cell]++] = t; });
}

bool MeshContacts::contains(std::uint32_t t, MeshFeature f, std::uint32_t id) const {
  const auto& ids = f == MeshFeature::edge ? tri_e_[t] : tri_v_[t];
  return ids[0] == id || ids[1] == id || ids[2] == id;
}

std::pair<const std::uint32_t*, const std::uint32_t*> MeshContacts::cell_triangles(Vec3 x) const {
  const long ix = static_cast<long>(std::floor((x.x - lo_.x) / h_));
  const long iy = static_cast<long>(std::floor((x.y - lo_.y) / h_));
  const long iz = static_cast<long>(std::floor((x.z - lo_.z) / h_));
  if (!(ix >= 0 && ix < nx_ && iy >= 0 && iy < ny_ && iz >= 0 && iz < nz_)) return {nullptr, nullptr};  // NaN too
  const std::size_t cell = static_cast<std::size_t>((iz * ny_ + iy) * nx_ + ix);
  return {cell_tris_.data() + cell_start_[cell], cell_tris_.data() + cell_start_[cell + 1]};
}

double MeshContacts::distance(Vec3 x, std::uint32_t t) const {
  const auto& c = corner_[t];
  const Vec3 q = closest_point_on_triangle(x, c[0], c[1], c[2]).point;
  return norm(q - x);
}

void MeshContacts::gather(Vec3 x, double reach, double time, std::vector<std::uint32_t>& out) const {
  const std::size_t before = out.size();
  // The meshes at rest share one lookup; each moving one is looked up in its body frame.
  const auto [t0, t1] = cell_triangles(x);
  for (const std::uint32_t* t = t0; t != t1; ++t)
    if (!moves_[tri_mesh_[*t]] && distance(x, *t) < reach) out.push_back(*t);
  if (!any_moves_) return;
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    if (!moves_[m]) continue;
    const Vec3 xb = to_body(m, x, time);
    const auto [b0, b1] = cell_triangles(xb);
    for (const std::uint32_t* t = b0; t != b1; ++t)
      if (tri_mesh_[*t] == m && distance(xb, *t) < reach) out.push_back(*t);
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(before), out.end());
}

void MeshContacts::find(Vec3 x, double r, std::uint32_t particle, std::vector<Contact>& out, double time) const {
  std::vector<std::uint32_t> tris;
  gather(x, r, time, tris);
  find_among(x, r, particle, tris.data(), tris.data() + tris.size(), out, time);
}

void MeshContacts::find_among(Vec3 xw, double r, std::uint32_t particle, const std::uint32_t* t0,
                              const std::uint32_t* t1, std::vector<Contact>& out, double time) const {
  if (t0 == t1) return;  // most particles: no candidate
  // The triangles the sphere touches, in triangle order (one buffer per thread, reused:
  // no allocation once it has grown).
  thread_local std::vector<Touch> touch;
  touch.clear();
  for (const std::uint32_t* tp = t0; tp != t1; ++tp) {
    const std::uint32_t t = *tp;
    const auto& c = corner_[t];
    const std::size_t mesh = tri_mesh_[t];
    const Vec3 x = to_body(mesh, xw, time);  // the mesh's body frame (xw itself at rest)
    // The plane's distance bounds the triangle's from below: most candidates beside a
    // contact lie in other planes and end here.
    const Vec3 n = normal_[t];
    const double s = dot(x - c[0], n);
    if (!(std::abs(s) < r)) continue;
    const TrianglePoint cp = closest_point_on_triangle(x, c[0], c[1], c[2]);
    Touch h;
    h.triangle = t;
    h.feature = cp.feature;
    h.point = cp.point;
    if (cp.feature == MeshFeature::face) {
      // The plane's distance and normal, as a plane wall computes them.
      h.distance = std::abs(s);
      h.eta = s >= 0.0 ? -n : n;
      h.feature_id = t;
    } else {
      const Vec3 d = cp.point - x;
      h.distance = norm(d);
      // A centre exactly on the edge or vertex: the face's normal.
      h.eta = h.distance > 0.0 ? (1.0 / h.distance) * d : -normal_[t];
      const auto idx = static_cast<std::size_t>(cp.index);
      h.feature_id = cp.feature == MeshFeature::edge ? tri_e_[t][idx] : tri_v_[t][idx];
    }
    if (!(h.distance < r)) continue;
    h.world = moves_[mesh] ? meshes_[mesh].motion.point(h.point, time) : h.point;
    touch.push_back(h);
  }
  const std::size_t nt = touch.size();
  auto at = [&](std::size_t k) -> const Touch& { return touch[k]; };
  // Ranks the candidates (faces first, then nearer, then lower index: a strict order, so
  // no two can remove each other and the best of a region always stays).
  auto before = [](const Touch& b, const Touch& a) {
    const bool bf = b.feature == MeshFeature::face, af = a.feature == MeshFeature::face;
    if (bf != af) return bf;
    if (b.distance != a.distance) return b.distance < a.distance;
    return b.triangle < a.triangle;
  };
  const double same_point = same * r;
  for (std::size_t k = 0; k < nt; ++k) {
    const Touch& a = at(k);
    bool keep = true;
    for (std::size_t j = 0; j < nt && keep; ++j) {
      if (j == k) continue;
      const Touch& b = at(j);
      if (!before(b, a)) continue;
      // The same point seen from another triangle: counted once.
      if (dot(b.world - a.world, b.world - a.world) <= same_point * same_point)
        keep = false;
      // An edge or vertex that a better-ranked triangle contains is no local minimum (or
      // the same one): from it the distance decreases, or stays, into that triangle.
      else if (a.feature != MeshFeature::face && contains(b.triangle, a.feature, a.feature_id))
        keep = false;
    }
    if (!keep) continue;
    Contact c;
    c.particle = particle;
    c.triangle = a.triangle;
    c.point = a.point;
    const std::size_t mesh = tri_mesh_[a.triangle];
    if (moves_[mesh]) {
      const WallMotion& mo = meshes_[mesh].motion;
      c.eta = mo.direction(a.eta, time);
      c.wall_velocity = mo.surface_velocity(a.world, time);
    } else {
      c.eta = a.eta;
    }
    c.overlap = r - a.distance;
    c.lever = a.distance;
    out.push_back(c);
  }
}

void MeshContacts::list_candidates(const ParticleStore& p, double margin, bool threads, double time,
                                   const std::vector<std::pair<std::uint32_t, std::uint32_t>>* runs) {
  const std::size_t n = p.size();
  double rmax = 0.0;
  for (std::size_t i = 0; i < n; ++i) rmax = std::max(rmax, p.radius[i]);
  if (rmax + margin > reach_) build_grid(rmax + margin);
  listed_time_ = time;
  listed_reach_ = rmax + margin;
  cand_start_.assign(n + 1, 0);
  // Particles [i0, i1): their counts in cand_start_[i + 1], their triangles appended to out.
  auto range = [&](std::size_t i0, std::size_t i1, std::vector<std::uint32_t>& out) {
    for (std::size_t i = i0; i < i1; ++i) {
      const std::size_t before = out.size();
      gather(p.position(i), p.radius[i] + margin, time, out);
      cand_start_[i + 1] = static_cast<std::uint32_t>(out.size() - before);
    }
  };
  cand_.clear();
  // Only the particles update() finds contacts for (runs in slot order): the others none.
  if (!runs) {
    in_particle_order(0, n, threads, range, cand_);
  } else {
    for (const auto& [i0, i1] : *runs) in_particle_order(i0, i1, threads, range, cand_);
  }
  for (std::size_t i = 0; i < n; ++i) cand_start_[i + 1] += cand_start_[i];
  listed_ = true;
  listed_all_ = runs == nullptr;
  if (runs) listed_runs_ = *runs;
  else listed_runs_.clear();
}

void MeshContacts::update(const ParticleStore& p, bool threads, std::size_t builds, double margin, double time,
                          const std::vector<std::pair<std::uint32_t, std::uint32_t>>* runs) {
  const std::size_t n = p.size();
  // A moving mesh has shifted against the particles by up to shift_bound since the
  // listing; with the particles' own drift (< margin / 2 between Verlet builds) the
  // candidates hold while that stays below margin / 2.
  bool shifted = false;
  for (std::size_t m = 0; m < meshes_.size() && any_moves_ && listed_; ++m)
    shifted = shifted || (moves_[m] && !(meshes_[m].motion.shift_bound(listed_time_, time, axis_reach_[m] + listed_reach_) <=
                                          0.5 * margin));
  // The candidates hold while no particle has moved more than the margin since they
  // were listed: listed again whenever the Verlet list was built (it is built before any
  // particle moves half its skin, the margin here).
  const bool same_runs = runs ? !listed_all_ && listed_runs_ == *runs : listed_all_;
  if (!listed_ || shifted || builds != builds_ || cand_start_.size() != n + 1 || !same_runs)
    list_candidates(p, margin, threads, time, runs);
  builds_ = builds;
  std::swap(prev_, contacts_);
  contacts_.clear();
  // The contacts of particles [i0, i1), with the history of their previous contacts.
  auto range = [&](std::size_t i0, std::size_t i1, std::vector<Contact>& out) {
    auto prev = std::lower_bound(prev_.begin(), prev_.end(), i0,
                                 [](const Contact& c, std::size_t i) { return c.particle < i; });
    std::uint64_t used = 0;
    for (std::size_t i = i0; i < i1; ++i) {
      // Most particles have no candidate: nothing to find, no history to carry (their
      // previous contacts, if any, are passed over at the next particle that has one).
      if (cand_start_[i] == cand_start_[i + 1]) continue;
      const std::size_t first = out.size();
      find_among(p.position(i), p.radius[i], static_cast<std::uint32_t>(i), cand_.data() + cand_start_[i],
                 cand_.data() + cand_start_[i + 1], out, time);
      while (prev != prev_.end() && prev->particle < i) ++prev;
      auto prev_end = prev;
      while (prev_end != prev_.end() && prev_end->particle == i) ++prev_end;
      used = 0;
      for (std::size_t k = first; k < out.size(); ++k) {
        Contact& c = out[k];
        const std::size_t mesh = tri_mesh_[c.triangle];
        long best = -1;
        double best_d2 = p.radius[i] * p.radius[i];
        for (auto q = prev; q != prev_end; ++q) {
          const auto slot = static_cast<std::size_t>(q - prev);
          if (slot < 64 && (used >> slot & 1)) continue;
          if (tri_mesh_[q->triangle] != mesh) continue;
          const double d2 = dot(q->point - c.point, q->point - c.point);
          if (d2 < best_d2) { best_d2 = d2; best = static_cast<long>(slot); }
        }
        if (best >= 0) {
          c.delta_t = prev[best].delta_t;
          c.touching = 1;
          if (best < 64) used |= std::uint64_t{1} << best;
        }
      }
    }
  };
  if (!runs) {
    in_particle_order(0, n, threads, range, contacts_);
  } else {
    for (const auto& [i0, i1] : *runs) in_particle_order(i0, i1, threads, range, contacts_);
  }
}

std::pair<std::size_t, std::size_t> MeshContacts::contacts_of(std::size_t i0, std::size_t i1) const {
  auto by_particle = [](const Contact& c, std::size_t i) { return c.particle < i; };
  const auto c0 = std::lower_bound(contacts_.begin(), contacts_.end(), i0, by_particle);
  const auto c1 = std::lower_bound(c0, contacts_.end(), i1, by_particle);
  return {static_cast<std::size_t>(c0 - contacts_.begin()), static_cast<std::size_t>(c1 - contacts_.begin())};
}

std::uint64_t MeshContacts::fingerprint() const {
  std::uint64_t h = 14695981039346656037ull;
  auto mix = [&](double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    h = (h ^ b) * 1099511628211ull;
  };
  for (const auto& c : corner_)
    for (const Vec3& v : c) { mix(v.x); mix(v.y); mix(v.z); }
  return h;
}

void MeshContacts::save_state(OutArchive& a) const {
  a.put(static_cast<std::uint64_t>(corner_.size()));
  a.put(fingerprint());
  a.put(static_cast<std::uint64_t>(contacts_.size()));
  for (const Contact& c : contacts_) {  // field by field: no padding bytes
    a.put(c.particle); a.put(c.triangle);
    a.put(c.point.x); a.put(c.point.y); a.put(c.point.z);
    a.put(c.delta_t.x); a.put(c.delta_t.y); a.put(c.delta_t.z);
    a.put(c.touching);
  }
}

void MeshContacts::load_state(InArchive& a) {
  std::uint64_t ntri = 0, fp = 0, nc = 0;
  a.get(ntri); a.get(fp);
  if (ntri != corner_.size() || fp != fingerprint())
    throw ArchiveError("its meshes differ from the scene's (" + std::to_string(ntri) + " triangles then, " +
                       std::to_string(corner_.size()) + " now, or moved vertices): was an STL file changed?");
  a.get(nc);
  if (nc > (std::uint64_t{1} << 32)) throw ArchiveError("its mesh contact record is corrupted");
  contacts_.assign(static_cast<std::size_t>(nc), Contact{});
  for (Contact& c : contacts_) {
    a.get(c.particle); a.get(c.triangle);
    a.get(c.point.x); a.get(c.point.y); a.get(c.point.z);
    a.get(c.delta_t.x); a.get(c.delta_t.y); a.get(c.delta_t.z);
    a.get(c.touching);
    if (c.triangle >= corner_.size() || c.touching > 1) throw ArchiveError("its mesh contact record is corrupted");
  }
  for (std::size_t k = 1; k < contacts_.size(); ++k)
    if (contacts_[k].particle < contacts_[k - 1].particle) throw ArchiveError("its mesh contact record is corrupted");
  listed_ = false;
}

void MeshContacts::permute(const std::vector<std::uint32_t>& from) {
  std::vector<std::uint32_t> to(from.size());
  for (std::size_t k = 0; k < from.size(); ++k) to[from[k]] = static_cast<std::uint32_t>(k);
  for (Contact& c : contacts_) c.particle = c.particle < to.size() ? to[c.particle] : c.particle;
  std::stable_sort(contacts_.begin(), contacts_.end(),
                   [](const Contact& a, const Contact& b) { return a.particle < b.particle; });
  listed_ = false;
}

void MeshContacts::remap(const std::vector<std::uint32_t>& from) {
  std::size_t n_old = 0;
  for (const Contact& c : contacts_) n_old = std::max<std::size_t>(n_old, c.particle + std::size_t{1});
  std::vector<std::uint32_t> to(n_old, new_particle);
  for (std::size_t k = 0; k < from.size(); ++k)
    if (from[k] != new_particle && from[k] < n_old) to[from[k]] = static_cast<std::uint32_t>(k);
  std::size_t kept = 0;
  for (const Contact& c : contacts_)
    if (to[c.particle] != new_particle) {
      contacts_[kept] = c;
      contacts_[kept++].particle = to[c.particle];
    }
  contacts_.resize(kept);
  std::stable_sort(contacts_.begin(), contacts_.end(),
                   [](const Contact& a, const Contact& b) { return a.particle < b.particle; });
  listed_ = false;
}

}  // namespace cdm
