// bmExcludedHead.h - a humeral head cut off its glenoid: the region of bone that belongs to the
// head, shared by the plan that finds it (Logic/Planning/bmJoinedHeadCut.h) and the CT import
// that leaves it out of a step's bone ("exclude_heads", Logic/IO/bmImport.h).
//
// With the socket (the glenoid face's sphere, centre S and radius Rs, shallower than the head's
// sphere, centre H and radius R) the joint lies between the two spheres and its middle on the
// spheroid |p - H| + |p - S| = R + Rs; a point is on the head's side when
//   f(p) = |p - H| + |p - S| - (R + Rs) <= shell,
// the shell (at least two voxels of f: f changes by at most twice a step) being emptied where
// the plan cuts. Without a socket, f(p) = |p - H| - R (shell at least one voxel).
//
// Units: world mm.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <array>
#include <cmath>
#include <optional>
#include <string>

namespace bm {

struct ExcludedHead {
  std::array<double, 3> centreMm{};                    ///< the head's sphere, mm
  double radiusMm = 0;                                 ///< mm, > 0
  std::optional<std::array<double, 3>> socketCentreMm; ///< the glenoid face's sphere, mm
  double socketRadiusMm = 0;                           ///< mm (with a socket centre), > radiusMm
  double shellMm = 0;                                  ///< the cut's thickness in f, mm (>= 0)

  /// f(p) above, mm.
  double F(const std::array<double, 3>& p) const {
    auto dist = [&](const std::array<double, 3>& c) {
      return std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                       (p[2] - c[2]) * (p[2] - c[2]));
    };
    return socketCentreMm ? dist(centreMm) + dist(*socketCentreMm) - (radiusMm + socketRadiusMm)
                          : dist(centreMm) - radiusMm;
  }
  /// Whether p is the head's (or the cut's): f(p) <= shellMm.
  bool Contains(const std::array<double, 3>& p) const { return F(p) <= shellMm; }
};

/// As JSON: {"centre_mm": [x, y, z], "radius_mm": r, "shell_mm": s} and, with a socket,
/// "socket_centre_mm" and "socket_radius_mm" (the CT import's "exclude_heads" entries).
nlohmann::json ExcludedHeadToJson(const ExcludedHead& head);
/// The inverse; throws std::runtime_error starting with `what` when `j` is not that shape or a
/// value is out of range (0 < r <= 200, r < socket radius <= 1000, 0 <= s <= 20, all finite).
ExcludedHead ExcludedHeadFromJson(const nlohmann::json& j, const std::string& what);

} // namespace bm
