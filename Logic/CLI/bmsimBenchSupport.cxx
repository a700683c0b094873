// bmsimBenchSupport.cxx - see bmsimBenchSupport.h.
#include "bmsimBenchSupport.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <fstream>
#include <thread>

#include "bmAnalyticGlenoid.h"
#include "bmBenchmark.h"
#include "bmSceneBone.h"
#include "bmsimCommand.h"
#ifdef BM_WITH_IO
#include "bmCTVoxmap.h"
#endif
#ifdef BM_WITH_OPENCL
#include "bmOpenCLDevice.h"
#endif

namespace bm::cli {

std::vector<int> Resolutions(const bm::cli::ParsedArgs& p, const std::string& name,
                             std::vector<int> def) {
  const auto v = p.Get(name);
  if (!v)
    return def;
  std::vector<int> out;
  for (const auto& s : bm::SplitCommaList(*v)) {
    size_t used = 0;
    int r = 0;
    try {
      r = std::stoi(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != s.size() || r < 8 || r > 4096)
      throw bm::cli::UsageError("--" + name + ": '" + s + "' is not a resolution in 8..4096");
    out.push_back(r);
  }
  if (out.empty())
    throw bm::cli::UsageError("--" + name + " is empty");
  return out;
}

std::string MachineName() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  return model + ", " + std::to_string(std::thread::hardware_concurrency()) + " logical cores";
}

/// The OpenCL device `choice` picks, with its platform, or why there is none. Call it only after
/// the grid's cells ran: they fork, and a parent that opened OpenCL must not.
std::string OpenCLDeviceName(const std::string& choice) {
#ifdef BM_WITH_OPENCL
  try {
    bm::OpenCLDeviceInfo info;
    bm::ChooseOpenCLDevice(choice, &info);
    return info.name + " (" + info.platform + ", " + info.version + ")";
  } catch (const std::exception& e) {
    return std::string("none: ") + e.what();
  }
#else
  (void)choice;
  return "none (this build has no OpenCL)";
#endif
}

#ifndef BM_WITH_IO
namespace {

/// The glenoid phantom's bone (bmAnalyticGlenoid.h's shape, placed as bmPhantom.h places it: face
/// centre (-60, 20, 40) mm, outward axis -x, elliptic face 40 x 29 mm, concave face of radius 35
/// mm, vault 25 mm deep, pilot hole r 4.0 mm x 10 mm) sampled straight into a voxmap, for builds
/// without BMIO (no ITK: no CT import). Box: the bone's bounds plus 0.625 mm, `resolution` voxels
/// along its longest side; fill = 0.5 + (signed distance to the surface) / spacing, clamped
/// (partial volume, as the CT import's resampling gives), all cortical. Units: mm.
bm::Voxmap AnalyticGlenoid(int resolution) {
  const double a = bm::glenoid::kA, b = bm::glenoid::kB, Rc = bm::glenoid::kRc, H = bm::glenoid::kH,
               rp = bm::glenoid::kRp, Dp = bm::glenoid::kDp, margin = 0.625;
  const double wTop = Rc - std::sqrt(Rc * Rc - a * a);
  // World x = -60 - w, y = 20 + v, z = 40 + u.
  const std::array<double, 3> lo{-60 - wTop - margin, 20 - b - margin, 40 - a - margin};
  const std::array<double, 3> hi{-60 + H + margin, 20 + b + margin, 40 + a + margin};
  double longest = 0;
  for (int q = 0; q < 3; ++q)
    longest = std::max(longest, hi[q] - lo[q]);
  const double h = longest / resolution;
  std::array<int, 3> dims;
  for (int q = 0; q < 3; ++q)
    dims[q] = int(std::ceil((hi[q] - lo[q]) / h));
  bm::Voxmap v(dims, h, {lo[0] + 0.5 * h, lo[1] + 0.5 * h, lo[2] + 0.5 * h});
  bm::Voxmap::Fill* fill = v.MutableFill();
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const auto p = v.GridToWorld({double(i), double(j), double(k)});
        const double w = -60 - p[0], vv = p[1] - 20, u = p[2] - 40;
        const double r = std::hypot(u, vv);
        // Signed distances (> 0 inside): elliptic wall (first order), vault floor, concave face
        // (a sphere of radius Rc centred Rc above the face centre), pilot hole.
        const double q = std::hypot(u / a, vv / b);
        const double g = q > 1e-9 ? std::hypot(u / (a * a), vv / (b * b)) / q : 1 / b;
        const double wall = (1 - q) / g;
        const double floor = w + H;
        const double face = std::sqrt(r * r + (w - Rc) * (w - Rc)) - Rc;
        const double hole = std::max(r - rp, -Dp - w);
        const double d = std::min({wall, floor, face, hole});
        fill[v.Index(i, j, k)] =
            bm::Voxmap::Fill(std::clamp(0.5 + d / h, 0.0, 1.0) * bm::Voxmap::kFull);
      }
  v.RebuildOccupancy();
  return v;
}

} // namespace
#endif

/// The scene's bone (bm::MakeSceneBone; without BMIO, the glenoid phantom's analytic bone).
bm::Voxmap BenchSceneBone(const bm::Scene& scene) {
#ifndef BM_WITH_IO
  if (scene.bone.type != "block" && scene.bone.ct.value("phantom", "") == "glenoid")
    return AnalyticGlenoid(scene.voxmapResolution);
#endif
  return bm::MakeSceneBone(scene);
}

} // namespace bm::cli
