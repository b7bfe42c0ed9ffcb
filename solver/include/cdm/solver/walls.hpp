#pragma once
/// @file walls.hpp
/// @brief Analytic walls: infinite planes, and the surfaces of finite cylinders and
/// cones (the lateral surface and each end cap a wall of its own), each optionally
/// moving (walls/wall_motion.hpp).
///
/// A wall meets a particle centre X through its gap (WallGap): the distance from the
/// closest point of the surface to X, positive on the domain side, and the unit normal
/// from the surface towards X. The contact laws see a wall as a body of infinite mass
/// whose surface moves with WallMotion::surface_velocity; the overlap is r − gap.
///
/// Plane: gap = (X − point)·normal, the unit normal into the domain, everywhere.
///
/// Surfaces of revolution (a cylinder when radius_start = radius_end, a cone otherwise):
/// the axis runs from `point` (s = 0, radius R₀) along the unit `normal` to s = L
/// (radius R₁). In X's meridian half-plane (s, ρ) the lateral surface is the segment
/// from (0, R₀) to (L, R₁), with parameter u = ((s, ρ − R₀)·(L, R₁ − R₀))/|·|².
///   lateral, 0 ≤ u ≤ 1 (its face): gap = signed distance to the segment's line,
///     positive towards the axis for a wall with particles inside, away from it outside;
///   a cap (a disc of the end's radius) where ρ ≤ its radius: gap = signed distance to
///     its plane, positive on the body's side for particles inside;
///   the rim circle of an end, where X is beyond the lateral face (u < 0 or u > 1) and
///     beyond the disc (ρ > its radius): gap = |X − rim point|, owned by the cap when the
///     end is capped, by the lateral surface when it is open — so a convex edge is one
///     contact, never two; in a concave corner (inside a capped cylinder) a particle
///     touches the lateral face and the cap face, as two planes.
/// A face is two-sided only near it: a centre more than a radius beyond a finite face
/// (gap < −r) is on the far side of the body, out of contact (a particle outside an
/// open drum is not pulled in).
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#include "cdm/solver/vec3.hpp"
#include "cdm/solver/walls/wall_motion.hpp"

namespace cdm {

enum class WallShape : std::uint8_t {
  plane,      ///< infinite plane
  lateral,    ///< lateral surface of a finite cylinder or cone
  cap_start,  ///< the disc closing the start end (s = 0)
  cap_end,    ///< the disc closing the far end (s = L)
};

/// Where a particle centre stands from a wall.
struct WallGap {
  double gap = std::numeric_limits<double>::infinity();  // centre to surface [m], > 0 on the domain side
  Vec3 normal;        // unit, from the surface towards the centre
  bool face = false;  // on a face of a finite surface (the gap signed; a rim's is not)
};

struct Wall {
  std::string name;
  Vec3 point;   // plane: any point of it; revolution: the axis at the start end [m]
  Vec3 normal;  // plane: unit normal into the domain; revolution: unit axis, start → end [-]
  int material = 0;
  WallShape shape = WallShape::plane;
  double radius_start = 0.0, radius_end = 0.0;  // revolution: R₀, R₁ [m]
  double length = 0.0;                          // revolution: L [m]
  bool inside = true;                           // revolution: the particles are inside it
  bool capped_start = false, capped_end = false;  // revolution: which ends are closed
  Vec3 across{1.0, 0.0, 0.0};  // revolution: a unit vector ⟂ the axis (for a centre on the axis) [-]
  WallMotion motion;

  /// A plane at rest through @p point with the unit @p normal into the domain.
  static Wall plane(std::string name, Vec3 point, Vec3 normal, int material) {
    Wall w;
    w.name = std::move(name);
    w.point = point;
    w.normal = normal;
    w.material = material;
    return w;
  }
  /// Plane only: signed distance of X from the plane [m], positive inside the domain.
  double distance(Vec3 X) const { return dot(X - point, normal); }
  /// The gap of the centre X (any shape). A finite face's gap below −@p r is none (+∞):
  /// a particle of radius r that far is on the other side of the body.
  WallGap gap(Vec3 X, double r) const;
  /// For listing candidates: a lower bound of the gap that changes by at most |ΔX| when
  /// X moves (a plane's signed distance; a finite surface's unsigned distance to the
  /// whole surface, rims included). A particle of radius r can touch the wall only where
  /// this is below r.
  double reach_distance(Vec3 X) const;
  /// This wall where its motion has brought it at time @p t [s].
  Wall at(double t) const;
  /// A bound [m] on how far the surface, as a set of points, moved from @p t0 to @p t1
  /// (zero for a rotation that maps it onto itself: a surface of revolution about its
  /// own axis, a plane about its normal).
  double shift_bound(double t0, double t1) const;
  /// The velocity [m/s] of the surface point @p x at time @p t.
  Vec3 surface_velocity(Vec3 x, double t) const { return motion.surface_velocity(x, t); }
};

}  // namespace cdm
