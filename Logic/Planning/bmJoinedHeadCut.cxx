#include "bmJoinedHeadCut.h"

#include "bmGlenoidGeometry.h"

#include <algorithm>
#include <optional>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <utility>

namespace bm {

namespace {

/// One line of the squared Euclidean distance transform (Felzenszwalb and Huttenlocher 2012): f
/// holds squared distances along the line (finite), replaced by the lower envelope's.
void DistanceLine(std::vector<double>& f, std::vector<double>& d, std::vector<int>& v,
                  std::vector<double>& z) {
  const int n = int(f.size());
  const double inf = std::numeric_limits<double>::infinity();
  d.resize(size_t(n));
  v.assign(size_t(n), 0);
  z.assign(size_t(n) + 1, inf);
  int k = 0;
  z[0] = -inf;
  for (int q = 1; q < n; ++q) {
    double s = 0;
    while (true) {
      const int p = v[size_t(k)];
      s = ((f[size_t(q)] + double(q) * q) - (f[size_t(p)] + double(p) * p)) / (2.0 * (q - p));
      if (s > z[size_t(k)] || k == 0)
        break;
      --k;
    }
    if (s <= z[size_t(k)]) { // k == 0 and q's parabola lies under p's everywhere
      v[0] = q;
      continue;
    }
    ++k;
    v[size_t(k)] = q;
    z[size_t(k)] = s;
    z[size_t(k) + 1] = inf;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[size_t(k) + 1] < q)
      ++k;
    const int p = v[size_t(k)];
    d[size_t(q)] = (q - p) * double(q - p) + f[size_t(p)];
  }
  f.swap(d);
}

/// Squared distance (voxels^2) of every voxel to the nearest voxel where !bone[v]; voxels
/// outside the grid count as not bone.
std::vector<double> SquaredDistance(const std::vector<uint8_t>& bone, const std::array<int, 3>& n) {
  const int64_t nx = n[0], ny = n[1];
  const double far = 1e18; // farther than any grid's squared diagonal
  std::vector<double> g(bone.size());
  for (size_t i = 0; i < bone.size(); ++i)
    g[i] = bone[i] ? far : 0.0;
  std::vector<double> f, d, z;
  std::vector<int> v;
  const int64_t step[3] = {1, nx, nx * ny};
  for (int a = 0; a < 3; ++a) {
    const int64_t len = n[size_t(a)];
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int64_t jb = 0; jb < n[size_t(b)]; ++jb)
      for (int64_t jc = 0; jc < n[size_t(c)]; ++jc) {
        const int64_t base = jb * step[b] + jc * step[c];
        // Padded by one outside voxel at each end: the grid's border is not bone.
        f.assign(size_t(len) + 2, 0.0);
        for (int64_t t = 0; t < len; ++t)
          f[size_t(t) + 1] = g[size_t(base + t * step[a])];
        DistanceLine(f, d, v, z);
        for (int64_t t = 0; t < len; ++t)
          g[size_t(base + t * step[a])] = f[size_t(t) + 1];
      }
  }
  return g;
}

} // namespace

std::vector<HeadSphere> FindHeadSpheres(const SegmentedBone& bone, const HeadCutOptions& o) {
  std::vector<HeadSphere> out;
  const auto& n = bone.Dims();
  const int64_t total = int64_t(n[0]) * n[1] * n[2];
  const double h = bone.Spacing();
  if (bone.NumBones() == 0)
    return out;
  std::vector<uint8_t> mask(static_cast<size_t>(total));
  for (int64_t v = 0; v < total; ++v)
    mask[size_t(v)] = bone.Label(v) > 0 ? 1 : 0;
  const std::vector<double> dist2 = SquaredDistance(mask, n);
  // The deepest voxel of each of the largest bones (labels 1, 2, ... by decreasing size).
  const int bones = std::min(bone.NumBones(), std::max(0, o.maxBones));
  std::vector<std::pair<double, int64_t>> deepest(size_t(bones), {-1.0, -1});
  for (int64_t v = 0; v < total; ++v) {
    const int l = bone.Label(v);
    if (l >= 1 && l <= bones && dist2[size_t(v)] > deepest[size_t(l - 1)].first)
      deepest[size_t(l - 1)] = {dist2[size_t(v)], v};
  }
  std::vector<int> order;
  for (int l = 1; l <= bones; ++l)
    if (deepest[size_t(l - 1)].second >= 0 &&
        std::sqrt(deepest[size_t(l - 1)].first) * h >= o.minHeadDepthMm)
      order.push_back(l);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return deepest[size_t(a - 1)].first > deepest[size_t(b - 1)].first;
  });
  const double cosMax = std::cos(35.0 * 3.14159265358979323846 / 180.0);
  const double scan = std::max(o.scanSpacingMm, h);
  for (int l : order) {
    const int64_t v0 = deepest[size_t(l - 1)].second;
    const int i0 = int(v0 % n[0]), j0 = int((v0 / n[0]) % n[1]),
              k0 = int(v0 / (int64_t(n[0]) * n[1]));
    SphereFit fit{bone.Centre(i0, j0, k0), std::sqrt(deepest[size_t(l - 1)].first) * h, 0};
    std::vector<Vec3> pts;
    bool ok = true;
    for (int it = 0; it < 8 && ok; ++it) {
      pts.clear();
      const double band = std::max(2 * h, 0.2 * fit.radiusMm);
      for (const auto& sp : bone.Surface()) {
        if (sp.label != l)
          continue;
        const Vec3 d = Sub(sp.p, fit.centre);
        const double r = Norm(d);
        if (r > 0 && std::abs(r - fit.radiusMm) <= band && Dot(sp.normal, d) >= cosMax * r)
          pts.push_back(sp.p);
      }
      if (pts.size() < 20) {
        ok = false;
        break;
      }
      try {
        const SphereFit next = FitSphere(pts);
        const bool settled = Distance(next.centre, fit.centre) < 1e-3 &&
                             std::abs(next.radiusMm - fit.radiusMm) < 1e-3;
        fit = next;
        if (settled)
          break;
      } catch (const std::invalid_argument&) {
        ok = false;
      }
    }
    if (!ok || fit.radiusMm < 12 || fit.radiusMm > 40 ||
        fit.rmsMm > 0.1 * fit.radiusMm + 0.5 * scan)
      continue;
    // Coverage: the share of 1024 directions (a Fibonacci sphere) from the centre in which a
    // surface point lies within max(half a voxel, a quarter of the scan's spacing) of the
    // sphere: a head's articular cap and the bone around it (about half of them).
    const double tight = std::max(0.5 * h, 0.25 * scan);
    constexpr int kDirections = 1024;
    std::vector<Vec3> dirs(kDirections);
    const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
    for (int q = 0; q < kDirections; ++q) {
      const double z = 1 - 2 * (q + 0.5) / kDirections, rr = std::sqrt(1 - z * z);
      dirs[size_t(q)] = {rr * std::cos(golden * q), rr * std::sin(golden * q), z};
    }
    std::vector<uint8_t> hit(kDirections, 0);
    for (const Vec3& p : pts) {
      const Vec3 d = Sub(p, fit.centre);
      const double r = Norm(d);
      if (std::abs(r - fit.radiusMm) > tight)
        continue;
      int best = 0;
      for (int q = 1; q < kDirections; ++q)
        if (Dot(dirs[size_t(q)], d) > Dot(dirs[size_t(best)], d))
          best = q;
      hit[size_t(best)] = 1;
    }
    double coverage = 0;
    Vec3 mean{0, 0, 0};
    for (int q = 0; q < kDirections; ++q)
      if (hit[size_t(q)])
        coverage += 1, mean = Add(mean, dirs[size_t(q)]);
    if (coverage == 0)
      continue;
    mean = Scale(mean, 1.0 / coverage);
    coverage /= kDirections;
    // The directions hit should fill a cap around their mean: for a cap of half-angle alpha
    // filled evenly the mean's length is (1 + cos alpha) / 2, so alpha follows from it, and the
    // share of the cap's directions hit is its fill. A ring (a cylinder's side) or rings (a
    // block's faces) have a short mean and fill little of the sphere they imply.
    const double rho = Norm(mean);
    const double cosAlpha = std::clamp(2 * rho - 1, -1.0, 1.0);
    const Vec3 axis = rho > 1e-9 ? Scale(mean, 1 / rho) : Vec3{0, 0, 1};
    double inside = 0, inCap = 0;
    for (int q = 0; q < kDirections; ++q)
      if (Dot(dirs[size_t(q)], axis) >= cosAlpha - 1e-12)
        inside += 1, inCap += hit[size_t(q)];
    const double fill = inside > 0 ? inCap / inside : 0;
    if (coverage < o.minCoverage || fill < o.minFill)
      continue;
    out.push_back({l, fit, coverage, fill});
  }
  return out;
}

std::vector<HeadCut> CutJoinedHeads(const Voxmap& vm, const SegmentedBone& bone,
                                    const HeadCutOptions& o) {
  std::vector<HeadCut> out;
  const auto& n = bone.Dims();
  const double h = bone.Spacing();
  const double cosMax = std::cos(35.0 * 3.14159265358979323846 / 180.0);
  const double scan = std::max(o.scanSpacingMm, h);
  for (const HeadSphere& sphere : FindHeadSpheres(bone, o)) {
    const int l = sphere.label;
    const SphereFit& fit = sphere.fit;
    HeadCut cut{vm, {}, fit.rmsMm, sphere.coverage, sphere.fill, 0};
    cut.head.centreMm = fit.centre;
    cut.head.radiusMm = fit.radiusMm;
    // The socket: the face where the joint is resolved, looking at the head's centre.
    std::vector<Vec3> face;
    for (const auto& sp : bone.Surface()) {
      if (sp.label != l)
        continue;
      const Vec3 d = Sub(fit.centre, sp.p);
      const double r = Norm(d);
      if (r > fit.radiusMm + h && r <= fit.radiusMm + 12 && Dot(sp.normal, d) >= cosMax * r)
        face.push_back(sp.p);
    }
    std::optional<SphereFit> socket;
    // A socket needs a face to fit: 3 % of the area of the head's 45-deg cap (a voxel-face
    // iso-surface holds about 1.5 points per voxel face area).
    if (double(face.size()) * h * h / 1.5 >= 0.03 * 1.84 * fit.radiusMm * fit.radiusMm) {
      try {
        const SphereFit s = FitSphere(face);
        if (s.radiusMm > fit.radiusMm + 1 && s.radiusMm <= 1000 &&
            Distance(s.centre, fit.centre) < s.radiusMm && s.rmsMm <= 0.1 * s.radiusMm + 0.5 * scan)
          socket = s;
      } catch (const std::invalid_argument&) {
      }
    }
    cut.head.shellMm = 2 * h;
    // The cone of the joint, seen from the head's centre: the socket's points around their mean
    // direction, 15 deg wider; with too few of them (a joint fused all over), 60 deg around the
    // way to the rest of the bone (the scapula beyond the glenoid). Beyond it the shell would cut
    // the head from its own neck, whose stump would then face the head as a socket does.
    Vec3 toJoint{0, 0, 0};
    double coneDeg = 60;
    if (socket) {
      cut.head.socketCentreMm = socket->centre;
      cut.head.socketRadiusMm = socket->radiusMm;
      for (const Vec3& p : face)
        toJoint = Add(toJoint, Normalized(Sub(p, fit.centre)));
      toJoint = Normalized(toJoint);
      double widest = 0;
      for (const Vec3& p : face)
        widest = std::max(widest, AngleDeg(Sub(p, fit.centre), toJoint));
      coneDeg = std::min(widest + 15, 85.0);
    } else {
      for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
          for (int i = 0; i < n[0]; ++i)
            if (bone.Label(bone.Index(i, j, k)) == l) {
              const Vec3 d = Sub(bone.Centre(i, j, k), fit.centre);
              if (Norm(d) > fit.radiusMm + 5)
                toJoint = Add(toJoint, d);
            }
      if (Norm(toJoint) == 0)
        continue;
      toJoint = Normalized(toJoint);
    }
    const double cone = std::cos(coneDeg * 3.14159265358979323846 / 180);
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          const int64_t v = bone.Index(i, j, k);
          if (bone.Label(v) != l)
            continue;
          const Vec3 p = bone.Centre(i, j, k);
          const double f = cut.head.F(p);
          const Vec3 d = Sub(p, fit.centre);
          if (f > 0 && f <= cut.head.shellMm && Dot(d, toJoint) >= cone * Norm(d)) {
            cut.voxmap.SetFill(vm.Index(i, j, k), 0);
            ++cut.cutVoxels;
          }
        }
    out.push_back(std::move(cut));
  }
  return out;
}

LandmarksOnCut
DetectCuttingAJoinedHead(const Voxmap& voxmap, const SegmentedBone& bone,
                         const std::function<GlenoidLandmarks(const SegmentedBone&)>& detect,
                         const HeadCutOptions& options) {
  LandmarksOnCut out;
  try {
    out.landmarks = detect(bone);
    return out;
  } catch (const NoGlenoidFound& first) {
    if (std::string(first.what()).rfind("both shoulders", 0) == 0)
      throw;
    for (HeadCut& c : CutJoinedHeads(voxmap, bone, options)) {
      SegmentedBone b(c.voxmap);
      try {
        out.landmarks = detect(b);
      } catch (const NoGlenoidFound&) {
        continue;
      }
      out.bone.emplace(std::move(b));
      out.cut.emplace(std::move(c));
      return out;
    }
    throw;
  }
}

std::string HeadCutSummary(const HeadCut& cut) {
  const ExcludedHead& h = cut.head;
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  s << "joined:      the humeral head touched the glenoid at the threshold (no joint space "
       "resolved): cut off along its sphere (centre ("
    << h.centreMm[0] << ", " << h.centreMm[1] << ", " << h.centreMm[2] << ") mm, radius "
    << h.radiusMm << " mm, RMS " << cut.rmsMm << " mm, its surface in " << 100 * cut.coverage
    << " % of the directions)";
  if (h.socketCentreMm)
    s << ", in the middle of the joint space to its socket (radius " << h.socketRadiusMm << " mm)";
  else
    s << ", just outside its sphere (the joint fused all over: no socket to fit)";
  s << ", " << cut.cutVoxels << " voxels emptied; the step scenes leave the head out\n";
  return s.str();
}

} // namespace bm
