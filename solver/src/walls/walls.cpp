#include "cdm/solver/walls.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cdm {

namespace {
/// X in the frame of a surface of revolution: axial coordinate s, radial distance ρ and
/// radial unit vector e, and the lateral segment's parameter u (walls.hpp).
struct Meridian {
  double s, rho, u;
  Vec3 e;
};

Meridian meridian(const Wall& w, Vec3 X) {
  const Vec3 d = X - w.point;
  Meridian m;
  m.s = dot(d, w.normal);
  const Vec3 q = d - m.s * w.normal;
  m.rho = norm(q);
  m.e = m.rho > 0.0 ? (1.0 / m.rho) * q : w.across;
  const double dr = w.radius_end - w.radius_start;
  m.u = (m.s * w.length + (m.rho - w.radius_start) * dr) / (w.length * w.length + dr * dr);
  return m;
}

/// The gap to the rim circle at axial position @p sr, radius @p rr.
WallGap rim(const Wall& w, const Meridian& m, double sr, double rr) {
  const double ds = m.s - sr, dr = m.rho - rr;
  const double dist = std::hypot(ds, dr);
  WallGap g;
  g.gap = dist;
  g.normal = dist > 0.0 ? (1.0 / dist) * (ds * w.normal + dr * m.e) : m.e;
  return g;
}

WallGap face(double gap, Vec3 normal, double r) {
  WallGap g;
  if (!(gap < -r)) {  // NaN stays a contact, for the integrator's finiteness check
    g.gap = gap;
    g.normal = normal;
    g.face = true;
  }
  return g;
}
}  // namespace

WallGap Wall::gap(Vec3 X, double r) const {
  if (shape == WallShape::plane) {
    WallGap g;
    g.gap = distance(X);
    g.normal = normal;
    return g;
  }
  const Meridian m = meridian(*this, X);
  const double R0 = radius_start, R1 = radius_end, L = length;
  switch (shape) {
    case WallShape::lateral: {
      if (m.u >= 0.0 && m.u <= 1.0) {
        // The segment's outward unit normal in the meridian plane, (−(R₁ − R₀), L)/|·|.
        const double dr = R1 - R0, len = std::hypot(L, dr);
        const double ms = -dr / len, mr = L / len;
        const double side = inside ? -1.0 : 1.0;
        return face(side * (m.s * ms + (m.rho - R0) * mr), side * (ms * normal + mr * m.e), r);
      }
      if (m.u < 0.0) return capped_start ? WallGap{} : rim(*this, m, 0.0, R0);
      return capped_end ? WallGap{} : rim(*this, m, L, R1);
    }
    case WallShape::cap_start:
      if (m.rho <= R0) return inside ? face(m.s, normal, r) : face(-m.s, -normal, r);
      return m.u < 0.0 ? rim(*this, m, 0.0, R0) : WallGap{};
    case WallShape::cap_end:
      if (m.rho <= R1) return inside ? face(L - m.s, -normal, r) : face(m.s - L, normal, r);
      return m.u > 1.0 ? rim(*this, m, L, R1) : WallGap{};
    case WallShape::plane: break;
  }
  return {};
}

double Wall::reach_distance(Vec3 X) const {
  if (shape == WallShape::plane) return distance(X);
  const Meridian m = meridian(*this, X);
  switch (shape) {
    case WallShape::lateral: {
      const double u = std::clamp(m.u, 0.0, 1.0);
      return std::hypot(m.s - u * length, m.rho - (radius_start + u * (radius_end - radius_start)));
    }
    case WallShape::cap_start: return std::hypot(m.s, std::max(m.rho - radius_start, 0.0));
    case WallShape::cap_end: return std::hypot(m.s - length, std::max(m.rho - radius_end, 0.0));
    case WallShape::plane: break;
  }
  return distance(X);
}

Wall Wall::at(double t) const {
  Wall w = *this;
  if (!motion.moving()) return w;
  w.point = motion.point(point, t);
  w.normal = motion.direction(normal, t);
  w.across = motion.direction(across, t);
  return w;
}

double Wall::shift_bound(double t0, double t1) const {
  if (motion.kind != WallMotion::Kind::rotation) return motion.shift_bound(t0, t1, 0.0);
  // A rotation that maps the surface onto itself moves none of it. Exact alignment is
  // tested to a relative 1e-12: what the rotation then moves is far below any skin.
  const Vec3 k = motion.axis;
  constexpr double tol = 1e-12;
  if (shape == WallShape::plane) {
    if (norm(cross(normal, k)) <= tol) return 0.0;
    return std::numeric_limits<double>::infinity();
  }
  const Vec3 off = point - motion.origin;
  const double scale = norm(off) + length + std::max(radius_start, radius_end);
  if (norm(cross(normal, k)) <= tol && norm(cross(off, k)) <= tol * scale) return 0.0;
  // Every point of the surface lies within this distance of the origin, so of the axis.
  const double reach = std::max(norm(off), norm(off + length * normal)) + std::max(radius_start, radius_end);
  return motion.shift_bound(t0, t1, reach);
}

}  // namespace cdm
