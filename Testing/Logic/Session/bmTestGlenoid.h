// bmTestGlenoid.h - an analytic glenoid for the session tests and benchmarks, without the CT
// import (no ITK in the session tests).
//
// The bone (world mm, the face centre at the origin, the reaming axis +z out of the bone) is the
// glenoid phantom's (bmAnalyticGlenoid.h) in its local frame, its vault cut 12 mm behind the face.
// The reamer goes about 2 mm deep.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "bmAnalyticGlenoid.h"
#include "bmScene.h"
#include "bmVoxmap.h"

namespace bmtest {

/// The phantom's glenoid (bmAnalyticGlenoid.h) with its vault cut 12 mm behind the face.
inline bool AnalyticGlenoidIsBone(double u, double v, double w) {
  return bm::glenoid::IsBone(u, v, w, 12.0);
}

/// The analytic glenoid at voxel spacing `spacing` (mm): whole voxels, bone where the centre is.
inline bm::Voxmap AnalyticGlenoidVoxmap(double spacing) {
  using namespace bm::glenoid;
  const double rim = kRc - std::sqrt(kRc * kRc - kA * kA);
  const std::array<double, 3> lo{-kA - spacing, -kB - spacing, -12.0 - spacing};
  const std::array<double, 3> hi{kA + spacing, kB + spacing, rim + spacing};
  std::array<int, 3> dims{};
  for (size_t a = 0; a < 3; ++a)
    dims[a] = int(std::ceil((hi[a] - lo[a]) / spacing)) + 1;
  bm::Voxmap v(dims, spacing, lo);
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const auto w = v.GridToWorld({double(i), double(j), double(k)});
        if (AnalyticGlenoidIsBone(w[0], w[1], w[2]))
          v.SetFill(v.Index(i, j, k), bm::Voxmap::kFull);
      }
  v.RebuildOccupancy();
  return v;
}

/// The glenoid scene's reamer (the built-in scene's tool, feed 0.1 mm/rev at 500 rpm) on the
/// analytic glenoid's grid: voxmap `voxmapResolution` over the scene's 41.25 mm, shell `shell`.
inline bm::Scene AnalyticGlenoidScene(int voxmapResolution, int shell) {
  nlohmann::json j = bm::Scene::Builtin("drilling").ToJson();
  j["tool"] = {{"type", "reamer"}};
  j["voxmap_resolution"] = voxmapResolution;
  j["shell_resolution"] = shell;
  j["threads"] = 2;
  j["trial"]["feed_mm_per_rev"] = 0.1;
  j["trial"]["speed_rpm"] = 500;
  j.erase("force_model");
  return bm::Scene::FromJson(j);
}

/// The voxel spacing (mm) of the glenoid scene at voxmap resolution `voxmapResolution`.
inline double AnalyticGlenoidSpacing(int voxmapResolution) {
  return 41.25 / voxmapResolution;
}

} // namespace bmtest
