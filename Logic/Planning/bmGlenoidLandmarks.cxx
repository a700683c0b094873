#include "bmGlenoidLandmarks.h"

#include "bmGlenoidGeometry.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace bm {

namespace {

const char* kPlaceHint = "; place the landmarks in the plan's \"landmarks\" (glenoid_centre_mm and "
                         "face_normal; trigonum_mm and inferior_angle_mm)";

std::string Mm(double v) {
  std::ostringstream s;
  s.precision(1);
  s << std::fixed << v << " mm";
  return s.str();
}

/// Extents (mm) of points along the two principal axes of their spread within the plane normal
/// to n: {major, minor}.
std::pair<double, double> InPlaneExtents(const std::vector<Vec3>& pts, const Vec3& n) {
  Vec3 e1 = Normalized(Cross(n, std::abs(n[2]) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0}));
  Vec3 e2 = Cross(n, e1);
  Vec3 mean{0, 0, 0};
  for (const auto& p : pts)
    mean = Add(mean, p);
  mean = Scale(mean, 1.0 / double(pts.size()));
  double sxx = 0, sxy = 0, syy = 0;
  for (const auto& p : pts) {
    const Vec3 d = Sub(p, mean);
    const double x = Dot(d, e1), y = Dot(d, e2);
    sxx += x * x, sxy += x * y, syy += y * y;
  }
  const double ang = 0.5 * std::atan2(2 * sxy, sxx - syy);
  const Vec3 a1 = Add(Scale(e1, std::cos(ang)), Scale(e2, std::sin(ang)));
  const Vec3 a2 = Cross(n, a1);
  double lo1 = 1e30, hi1 = -1e30, lo2 = 1e30, hi2 = -1e30;
  for (const auto& p : pts) {
    const Vec3 d = Sub(p, mean);
    lo1 = std::min(lo1, Dot(d, a1)), hi1 = std::max(hi1, Dot(d, a1));
    lo2 = std::min(lo2, Dot(d, a2)), hi2 = std::max(hi2, Dot(d, a2));
  }
  const double x = hi1 - lo1, y = hi2 - lo2;
  return {std::max(x, y), std::min(x, y)};
}

Vec3 Mean(const std::vector<Vec3>& pts) {
  Vec3 m{0, 0, 0};
  for (const auto& p : pts)
    m = Add(m, p);
  return Scale(m, 1.0 / double(std::max<size_t>(1, pts.size())));
}

struct Joint {
  int scapula = 0;
  Vec3 centre{}, normal{};
  SphereFit head;
};

Joint FindJoint(const SegmentedBone& bone, const DetectionOptions& opt) {
  const double h = bone.Spacing();
  const auto& surf = bone.Surface();
  std::map<std::pair<int, int>, std::vector<size_t>> facing;
  for (size_t s = 0; s < surf.size(); ++s) {
    const SurfacePoint& sp = surf[s];
    for (double d = 0.5 * h; d <= opt.maxJointGapMm; d += 0.5 * h) {
      const int lab = bone.LabelAt(AddScaled(sp.p, sp.normal, d));
      if (lab == sp.label) {
        if (d >= 1.5 * h)
          break;
        continue;
      }
      if (lab != 0) {
        facing[{sp.label, lab}].push_back(s);
        break;
      }
    }
  }
  if (facing.empty())
    throw NoGlenoidFound("no glenoid found: no two bones face each other across a joint space of "
                         "at most " +
                         Mm(opt.maxJointGapMm) + kPlaceHint);
  std::vector<std::pair<std::pair<int, int>, std::vector<size_t>>> cands(facing.begin(),
                                                                         facing.end());
  std::sort(cands.begin(), cands.end(),
            [](const auto& a, const auto& b) { return a.second.size() > b.second.size(); });
  std::string reasons;
  for (size_t c = 0; c < cands.size() && c < 8; ++c) {
    const auto [L, M] = cands[c].first;
    std::vector<Vec3> patch, normals;
    for (size_t s : cands[c].second)
      patch.push_back(surf[s].p), normals.push_back(surf[s].normal);
    const std::string what = "bone " + std::to_string(L) + " facing bone " + std::to_string(M);
    auto reject = [&](const std::string& why) {
      reasons += (reasons.empty() ? "" : "; ") + what + ": " + why;
    };
    if (patch.size() < 30) {
      reject("joint surface too small");
      continue;
    }
    SphereFit fs;
    try {
      fs = FitSphere(patch);
    } catch (const std::invalid_argument&) {
      reject("joint surface is flat");
      continue;
    }
    double side = 0;
    for (size_t i = 0; i < patch.size(); ++i)
      side += Dot(Sub(patch[i], fs.centre), normals[i]);
    if (side >= 0) {
      reject("its joint surface is convex (a head, not a socket)");
      continue;
    }
    if (fs.radiusMm < 15 || fs.radiusMm > 100) {
      reject("its joint surface's radius of curvature, " + Mm(fs.radiusMm) +
             ", is outside a glenoid's 15-100 mm");
      continue;
    }
    const Vec3 c0 = Mean(patch);
    const Vec3 nApprox = Normalized(Sub(fs.centre, c0));
    const auto [major, minor] = InPlaneExtents(patch, nApprox);
    if (major < opt.minFaceHeightMm || minor < opt.minFaceWidthMm) {
      reject("joint surface " + Mm(major) + " x " + Mm(minor) + ", smaller than a glenoid (" +
             Mm(opt.minFaceHeightMm) + " x " + Mm(opt.minFaceWidthMm) + ")");
      continue;
    }
    std::vector<Vec3> head;
    double convex = 0;
    for (const auto& sp : surf)
      if (sp.label == M && Distance(sp.p, c0) <= 0.5 * major + 15 &&
          Dot(sp.normal, Sub(c0, sp.p)) > 0)
        head.push_back(sp.p);
    SphereFit fh;
    try {
      fh = FitSphere(head);
    } catch (const std::invalid_argument&) {
      reject("no humeral head surface");
      continue;
    }
    for (const auto& sp : surf)
      if (sp.label == M && Distance(sp.p, c0) <= 0.5 * major + 15 &&
          Dot(sp.normal, Sub(c0, sp.p)) > 0)
        convex += Dot(Sub(sp.p, fh.centre), sp.normal);
    if (convex <= 0 || fh.radiusMm < 12 || fh.radiusMm > 40 || fh.rmsMm > 0.1 * fh.radiusMm) {
      reject("the facing bone is no humeral head (sphere radius " + Mm(fh.radiusMm) + ", rms " +
             Mm(fh.rmsMm) + ")");
      continue;
    }
    // The head sits in the socket: its centre lies within the face's sphere, and it is no
    // larger than the socket's curvature allows.
    if (Distance(fh.centre, fs.centre) >= fs.radiusMm || fh.radiusMm > fs.radiusMm + 10) {
      reject("the facing bone's sphere (radius " + Mm(fh.radiusMm) +
             ") does not sit in the socket (radius " + Mm(fs.radiusMm) + ")");
      continue;
    }
    Joint j;
    j.scapula = L;
    j.centre = c0;
    j.normal = Normalized(Sub(fh.centre, c0));
    j.head = fh;
    return j;
  }
  throw NoGlenoidFound("no glenoid found (" + reasons + ")" + kPlaceHint);
}

/// Centroid of the voxels of `label` within `radius` of the voxel farthest from `from`
/// (in-plane distance on slice k when k >= 0, else 3D over the whole grid).
std::optional<Vec3> FarthestEnd(const SegmentedBone& b, int label, const Vec3& from, int k,
                                double radius) {
  const auto& d = b.Dims();
  const int k0 = k >= 0 ? k : 0, k1 = k >= 0 ? k + 1 : d[2];
  if (k >= d[2])
    return std::nullopt;
  auto dist2 = [&](const Vec3& p) {
    const double dx = p[0] - from[0], dy = p[1] - from[1], dz = k >= 0 ? 0.0 : p[2] - from[2];
    return dx * dx + dy * dy + dz * dz;
  };
  double best = -1;
  Vec3 far{};
  for (int kk = k0; kk < k1; ++kk)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        if (b.Label(b.Index(i, j, kk)) == label) {
          const Vec3 p = b.Centre(i, j, kk);
          const double e = dist2(p);
          if (e > best)
            best = e, far = p;
        }
  if (best < 0)
    return std::nullopt;
  Vec3 sum{0, 0, 0};
  double w = 0;
  for (int kk = k0; kk < k1; ++kk)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        const int64_t idx = b.Index(i, j, kk);
        if (b.Label(idx) != label)
          continue;
        const Vec3 p = b.Centre(i, j, kk);
        if (Distance(p, far) <= radius) {
          sum = AddScaled(sum, p, b.Fraction(idx));
          w += b.Fraction(idx);
        }
      }
  return Scale(sum, 1.0 / w);
}

Vec3 UpAxis(const Vec3& n) {
  const Vec3 z{0, 0, 1};
  return Normalized(AddScaled(std::abs(n[2]) < 0.95 ? z : Vec3{0, 1, 0}, n,
                              -Dot(std::abs(n[2]) < 0.95 ? z : Vec3{0, 1, 0}, n)));
}

} // namespace

LandmarkOverrides LandmarkOverrides::FromJson(const nlohmann::json& j) {
  if (!j.is_object())
    throw std::invalid_argument("\"landmarks\" must be an object");
  LandmarkOverrides o;
  for (const auto& [key, value] : j.items()) {
    if (key == "source" || key == "rim_mm" || key == "humeral_head")
      continue; // what GlenoidLandmarks::ToJson adds for the reader, not a landmark
    std::optional<Vec3>* slot = key == "glenoid_centre_mm"   ? &o.glenoidCentre
                                : key == "face_normal"       ? &o.faceNormal
                                : key == "trigonum_mm"       ? &o.trigonum
                                : key == "inferior_angle_mm" ? &o.inferiorAngle
                                                             : nullptr;
    if (!slot)
      throw std::invalid_argument("landmarks: unknown key \"" + key +
                                  "\" (glenoid_centre_mm, face_normal, trigonum_mm, "
                                  "inferior_angle_mm)");
    if (!value.is_array() || value.size() != 3)
      throw std::invalid_argument("landmarks: \"" + key + "\" must be [x, y, z]");
    Vec3 v;
    for (int a = 0; a < 3; ++a) {
      if (!value[size_t(a)].is_number() || !std::isfinite(value[size_t(a)].get<double>()))
        throw std::invalid_argument("landmarks: \"" + key + "\" must hold 3 finite numbers");
      v[size_t(a)] = value[size_t(a)].get<double>();
    }
    if (slot == &o.faceNormal) {
      if (Norm(v) < 1e-9)
        throw std::invalid_argument("landmarks: \"face_normal\" must not be zero");
      v = Normalized(v);
    }
    *slot = v;
  }
  return o;
}

nlohmann::json GlenoidLandmarks::ToJson() const {
  nlohmann::json rimJ = nlohmann::json::array();
  for (const auto& p : rim)
    rimJ.push_back(p);
  nlohmann::json j = {{"glenoid_centre_mm", glenoidCentre},
                      {"face_normal", faceNormal},
                      {"trigonum_mm", trigonum},
                      {"inferior_angle_mm", inferiorAngle},
                      {"source",
                       {{"glenoid_centre", centreSource},
                        {"face_normal", normalSource},
                        {"trigonum", trigonumSource},
                        {"inferior_angle", inferiorSource}}},
                      {"rim_mm", rimJ}};
  if (humeralHeadFound)
    j["humeral_head"] = {{"centre_mm", humeralHeadCentre}, {"radius_mm", humeralHeadRadiusMm}};
  return j;
}

GlenoidLandmarks DetectLandmarks(const SegmentedBone& bone, const LandmarkOverrides& ov,
                                 const DetectionOptions& opt) {
  GlenoidLandmarks L;
  Vec3 c, n;
  if (ov.glenoidCentre && ov.faceNormal) {
    c = *ov.glenoidCentre;
    n = *ov.faceNormal;
    // The scapula: the bone of the surface point nearest the given centre.
    double best = 1e30;
    for (const auto& sp : bone.Surface())
      if (Distance(sp.p, c) < best)
        best = Distance(sp.p, c), L.scapulaLabel = sp.label;
    if (best > 10)
      throw NoGlenoidFound("the given glenoid centre is " + Mm(best) +
                           " from the nearest bone surface; place it on the glenoid face");
  } else {
    const Joint j = FindJoint(bone, opt);
    L.scapulaLabel = j.scapula;
    L.humeralHeadFound = true;
    L.humeralHeadCentre = j.head.centre;
    L.humeralHeadRadiusMm = j.head.radiusMm;
    c = ov.glenoidCentre ? *ov.glenoidCentre : j.centre;
    n = ov.faceNormal ? *ov.faceNormal : j.normal;
  }
  L.centreSource = ov.glenoidCentre ? "user" : "detected";
  L.normalSource = ov.faceNormal ? "user" : "detected";
  // Rim, plane and centre around the axis.
  std::vector<Vec3> cands;
  std::vector<Vec3> candNormals;
  for (const auto& sp : bone.Surface())
    if (sp.label == L.scapulaLabel && Distance(sp.p, c) <= opt.rimSearchRadiusMm + 15 &&
        Dot(Sub(sp.p, c), n) >= -12)
      cands.push_back(sp.p), candNormals.push_back(sp.normal);
  if (cands.size() < size_t(opt.rimPoints))
    throw NoGlenoidFound("no glenoid found: no glenoid surface around the joint" +
                         std::string(kPlaceHint));
  for (int it = 0; it < kRimIterations; ++it) {
    const Vec3 eu = UpAxis(n), ev = Cross(n, eu);
    L.rim = SupportRim(cands, c, n, eu, ev, opt.rimPoints, opt.rimSearchRadiusMm);
    const PlaneFit plane = FitRimPlane(L.rim);
    const Vec3 before = n, centreBefore = c;
    if (!ov.faceNormal)
      n = Dot(plane.normal, n) < 0 ? Scale(plane.normal, -1) : plane.normal;
    if (!ov.glenoidCentre) {
      double sum = 0;
      int count = 0;
      for (size_t i = 0; i < cands.size(); ++i) {
        const Vec3 d = Sub(cands[i], plane.centroid);
        const double w = Dot(d, n);
        if (Norm(AddScaled(d, n, -w)) <= 2.5 && Dot(candNormals[i], n) > 0.5 && std::abs(w) < 20)
          sum += w, ++count;
      }
      if (count == 0)
        throw NoGlenoidFound("no glenoid found: no articular face on the rim plane's axis" +
                             std::string(kPlaceHint));
      c = AddScaled(plane.centroid, n, sum / count);
    }
    if (AngleDeg(before, n) < 1e-3 && Distance(centreBefore, c) < 1e-3)
      break;
  }
  L.glenoidCentre = c;
  L.faceNormal = n;
  if (L.humeralHeadFound && Dot(Sub(L.humeralHeadCentre, c), n) < 0 && !ov.faceNormal)
    L.faceNormal = Scale(n, -1);
  // The face: inside 80 % of the rim's radius in the rim's direction, facing out of the joint.
  {
    const Vec3 eu = UpAxis(n), ev = Cross(n, eu);
    std::vector<std::pair<double, double>> rimPolar; // angle, radius
    for (const auto& p : L.rim) {
      const Vec3 d = Sub(p, c);
      rimPolar.push_back({std::atan2(Dot(d, ev), Dot(d, eu)), std::hypot(Dot(d, eu), Dot(d, ev))});
    }
    for (size_t i = 0; i < cands.size(); ++i) {
      const Vec3 d = Sub(cands[i], c);
      const double u = Dot(d, eu), v = Dot(d, ev), ang = std::atan2(v, u);
      double rr = 0, bestA = 10;
      for (const auto& [a, r] : rimPolar) {
        const double da = std::abs(std::remainder(a - ang, 2 * 3.14159265358979323846));
        if (da < bestA)
          bestA = da, rr = r;
      }
      if (std::hypot(u, v) <= 0.8 * rr && Dot(candNormals[i], n) > 0.5 && Dot(d, n) >= -10)
        L.face.push_back(cands[i]);
    }
  }
  // Scapular-plane landmarks.
  if (ov.trigonum) {
    L.trigonum = *ov.trigonum;
    L.trigonumSource = "user";
  } else {
    const double kf = (c[2] - bone.Origin()[2]) / bone.Spacing();
    const int k0 = int(std::floor(kf));
    const double t = kf - k0;
    const auto a = FarthestEnd(bone, L.scapulaLabel, c, k0, 3.0);
    const auto b = FarthestEnd(bone, L.scapulaLabel, c, k0 + 1, 3.0);
    if (!a || !b)
      throw NoGlenoidFound("no trigonum found: the scapula does not reach the glenoid centre's "
                           "axial plane; place \"trigonum_mm\"");
    L.trigonum = Add(Scale(*a, 1 - t), Scale(*b, t));
    L.trigonumSource = "detected";
  }
  if (Distance(L.trigonum, c) < 50)
    throw NoGlenoidFound("no trigonum found: the scapula ends " + Mm(Distance(L.trigonum, c)) +
                         " medial of the glenoid centre (a scapular body reaches >= 50 mm); place "
                         "\"trigonum_mm\"");
  if (ov.inferiorAngle) {
    L.inferiorAngle = *ov.inferiorAngle;
    L.inferiorSource = "user";
  } else {
    const auto a = FarthestEnd(bone, L.scapulaLabel, c, -1, 5.0);
    if (!a)
      throw NoGlenoidFound("no inferior angle found; place \"inferior_angle_mm\"");
    L.inferiorAngle = *a;
    L.inferiorSource = "detected";
  }
  if (Distance(L.inferiorAngle, c) < 50)
    throw NoGlenoidFound("no inferior angle found: the scapula reaches only " +
                         Mm(Distance(L.inferiorAngle, c)) +
                         " from the glenoid centre (the CT may not hold the whole scapula); place "
                         "\"inferior_angle_mm\"");
  return L;
}

} // namespace bm
