#include "bmGlenoidLandmarks.h"

#include "bmGlenoidGeometry.h"
#include "bmScapularSpine.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <tuple>

namespace bm {

namespace {

/// A joint found within this of a placed centre or face point is the placed glenoid's (half a
/// glenoid's height, 25-35 mm; the other shoulder's joint lies some 300 mm away).
constexpr double kSameJointMm = 15.0;
/// Radius of the face patch whose mean normal starts a placed glenoid's rim search, mm (inside
/// a glenoid's half-width of 11-15 mm).
constexpr double kPlacedFaceRadiusMm = 8.0;

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
  const auto [x, y] = ExtentsAlong(pts, mean, a1, Cross(n, a1));
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
  // The scan's coarsest spacing: a patch loses up to a voxel at each edge to partial volume, and
  // a sphere sampled on slices of thickness s is a staircase of about s / 2 residual.
  const double scan = std::max(h, opt.scanSpacingMm);
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
  std::vector<Vec3> rejectedAt;
  for (size_t c = 0; c < cands.size() && c < 8; ++c) {
    const auto [L, M] = cands[c].first;
    std::vector<Vec3> patch, normals;
    for (size_t s : cands[c].second)
      patch.push_back(surf[s].p), normals.push_back(surf[s].normal);
    const Vec3 at = Mean(patch);
    std::ostringstream where;
    where.precision(0);
    where << std::fixed << " at (" << at[0] << ", " << at[1] << ", " << at[2] << ") mm";
    const std::string what =
        "bone " + std::to_string(L) + " facing bone " + std::to_string(M) + where.str();
    auto reject = [&](const std::string& why) {
      reasons += (reasons.empty() ? "" : "; ") + what + ": " + why;
      rejectedAt.push_back(at);
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
    const Vec3& c0 = at;
    const Vec3 nApprox = Normalized(Sub(fs.centre, c0));
    if (opt.side != ShoulderSide::Any && (nApprox[0] > 0) != (opt.side == ShoulderSide::Left)) {
      reject(std::string("it faces the patient's ") + (nApprox[0] > 0 ? "left" : "right") +
             " (the " + ShoulderSideName(opt.side) + " shoulder was asked for)");
      continue;
    }
    const auto [major, minor] = InPlaneExtents(patch, nApprox);
    const double minMajor = opt.minFaceHeightMm - 2 * scan,
                 minMinor = opt.minFaceWidthMm - 2 * scan;
    if (major < minMajor || minor < minMinor) {
      reject("joint surface " + Mm(major) + " x " + Mm(minor) + ", smaller than a glenoid (" +
             Mm(minMajor) + " x " + Mm(minMinor) + " at this scan's " + Mm(scan) + " spacing)");
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
    if (convex <= 0) {
      // A head whose cancellous interior is darker than the threshold and was not filled (its
      // cortex has gaps at this scan's spacing) is a shell: the inner surfaces face the joint
      // too. Its outer surface (normals away from the sphere's centre) then lies outside the
      // inner ones, and the head is its sphere.
      std::vector<Vec3> outer;
      double rOut = 0, rIn = 0;
      int in = 0;
      for (const auto& sp : surf)
        if (sp.label == M && Distance(sp.p, c0) <= 0.5 * major + 15 &&
            Dot(sp.normal, Sub(c0, sp.p)) > 0) {
          const double r = Distance(sp.p, fh.centre);
          if (Dot(Sub(sp.p, fh.centre), sp.normal) > 0)
            outer.push_back(sp.p), rOut += r;
          else
            ++in, rIn += r;
        }
      // Its outer surface must be a head's, not a few knobs: at least a quarter of the area of
      // the sphere's 45-deg cap toward the joint (2 pi R^2 (1 - cos 45 deg); a voxel-face
      // iso-surface holds about 1.5 points per voxel face area).
      const double h = bone.Spacing(), R = fh.radiusMm;
      const double outerArea = double(outer.size()) * h * h / 1.5;
      if (outerArea >= 0.25 * 1.84 * R * R && in > 0 &&
          rOut / double(outer.size()) >= rIn / in + 0.5) {
        try {
          fh = FitSphere(outer);
          convex = 1;
        } catch (const std::invalid_argument&) {
        }
      }
    }
    const double maxRms = 0.1 * fh.radiusMm + 0.5 * scan;
    if (convex <= 0 || fh.radiusMm < 12 || fh.radiusMm > 40 || fh.rmsMm > maxRms) {
      reject("the facing bone is no humeral head (sphere radius " + Mm(fh.radiusMm) +
             " of 12-40 mm, rms " + Mm(fh.rmsMm) + " of at most " + Mm(maxRms) + ")");
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
  throw NoGlenoidFound("no glenoid found (" + reasons + ")" + kPlaceHint, rejectedAt);
}

/// Centroid of the voxels of `label` within `radius` of the voxel farthest from `from`
/// (in-plane distance on slice k when k >= 0, else 3D over the whole grid; only voxels at or
/// below zMax), and that farthest voxel's centre (the tip).
struct End {
  Vec3 centroid{}, tip{};
};
std::optional<End> FarthestEnd(const SegmentedBone& b, int label, const Vec3& from, int k,
                               double radius,
                               double zMax = std::numeric_limits<double>::infinity()) {
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
          if (p[2] > zMax)
            continue;
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
        if (Distance(p, far) <= radius && p[2] <= zMax) {
          sum = AddScaled(sum, p, b.Fraction(idx));
          w += b.Fraction(idx);
        }
      }
  return End{Scale(sum, 1.0 / w), far};
}

/// Shares of the samples at 1.5 to 12 mm ahead of c along n, and behind it, that lie in bone
/// `label`: {ahead, behind}.
std::pair<double, double> BoneAheadAndBehind(const SegmentedBone& b, int label, const Vec3& c,
                                             const Vec3& n) {
  int ahead = 0, behind = 0, count = 0;
  for (double d = 1.5; d <= 12.0; d += 0.5 * b.Spacing(), ++count) {
    ahead += b.LabelAt(AddScaled(c, n, d)) == label;
    behind += b.LabelAt(AddScaled(c, n, -d)) == label;
  }
  return {double(ahead) / count, double(behind) / count};
}

/// The scan edges (of x, y, z where axes[a]) that p lies within `reach` of: "" when none.
std::string NearScanEdge(const std::optional<Box3>& scan, const Vec3& p, double reach,
                         std::array<bool, 3> axes) {
  if (!scan)
    return "";
  static const char* lo[3] = {"right", "anterior", "inferior"};
  static const char* hi[3] = {"left", "posterior", "superior"};
  std::string edges;
  for (int a = 0; a < 3; ++a) {
    if (!axes[size_t(a)])
      continue;
    if (p[size_t(a)] - scan->lo[size_t(a)] <= reach)
      edges += std::string(edges.empty() ? "" : ", ") + lo[a];
    if (scan->hi[size_t(a)] - p[size_t(a)] <= reach)
      edges += std::string(edges.empty() ? "" : ", ") + hi[a];
  }
  return edges;
}

/// The label of the bone whose surface point is nearest p, and that distance (mm).
std::pair<int, double> NearestBone(const SegmentedBone& bone, const Vec3& p) {
  double best = 1e30;
  int label = 0;
  for (const auto& sp : bone.Surface())
    if (Distance(sp.p, p) < best)
      best = Distance(sp.p, p), label = sp.label;
  return {label, best};
}

/// The outward normal of bone `label`'s face around `c`: the mean of its surface normals within
/// kPlacedFaceRadiusMm (a glenoid is 25-35 mm high; the patch stays on the face for a click
/// within a few mm of its centre). The rim iteration then refines it to the rim plane's normal.
Vec3 FaceNormalAround(const SegmentedBone& bone, int label, const Vec3& c) {
  Vec3 sum{};
  for (const auto& sp : bone.Surface())
    if (sp.label == label && Distance(sp.p, c) <= kPlacedFaceRadiusMm)
      sum = Add(sum, sp.normal);
  const double len = Norm(sum);
  if (!(len > 0))
    throw NoGlenoidFound("no bone surface within " + Mm(kPlacedFaceRadiusMm) +
                         " of the placed glenoid centre; click on the glenoid face");
  return Scale(sum, 1.0 / len);
}

Vec3 UpAxis(const Vec3& n) {
  const Vec3 z{0, 0, 1};
  return Normalized(AddScaled(std::abs(n[2]) < 0.95 ? z : Vec3{0, 1, 0}, n,
                              -Dot(std::abs(n[2]) < 0.95 ? z : Vec3{0, 1, 0}, n)));
}

} // namespace

const char* ShoulderSideName(ShoulderSide side) {
  return side == ShoulderSide::Left ? "left" : side == ShoulderSide::Right ? "right" : "any";
}

LandmarkOverrides LandmarkOverrides::FromJson(const nlohmann::json& j) {
  if (!j.is_object())
    throw std::invalid_argument("\"landmarks\" must be an object");
  LandmarkOverrides o;
  for (const auto& [key, value] : j.items()) {
    if (key == "source" || key == "rim_mm" || key == "humeral_head" || key == "side" ||
        key == "not_available")
      continue; // what GlenoidLandmarks::ToJson adds for the reader, not a landmark
    if (key == "rim_points_mm") {
      if (!value.is_array() || value.size() > 1000)
        throw std::invalid_argument("landmarks: \"rim_points_mm\" must be a list of [x, y, z]");
      for (const auto& q : value) {
        if (!q.is_array() || q.size() != 3)
          throw std::invalid_argument("landmarks: \"rim_points_mm\" must be a list of [x, y, z]");
        Vec3 v;
        for (int a = 0; a < 3; ++a) {
          if (!q[size_t(a)].is_number() || !std::isfinite(q[size_t(a)].get<double>()))
            throw std::invalid_argument("landmarks: \"rim_points_mm\" must hold finite numbers");
          v[size_t(a)] = q[size_t(a)].get<double>();
        }
        o.rimPoints.push_back(v);
      }
      if (o.rimPoints.size() < 3)
        throw std::invalid_argument("landmarks: \"rim_points_mm\" needs at least 3 points on the "
                                    "glenoid's rim");
      continue;
    }
    std::optional<Vec3>* slot = key == "glenoid_centre_mm"   ? &o.glenoidCentre
                                : key == "face_normal"       ? &o.faceNormal
                                : key == "trigonum_mm"       ? &o.trigonum
                                : key == "inferior_angle_mm" ? &o.inferiorAngle
                                : key == "face_point_mm"     ? &o.facePoint
                                                             : nullptr;
    if (!slot)
      throw std::invalid_argument("landmarks: unknown key \"" + key +
                                  "\" (glenoid_centre_mm, face_normal, trigonum_mm, "
                                  "inferior_angle_mm, rim_points_mm, face_point_mm)");
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
                      {"source",
                       {{"glenoid_centre", centreSource},
                        {"face_normal", normalSource},
                        {"trigonum", trigonumSource},
                        {"inferior_angle", inferiorSource}}},
                      {"side", side},
                      {"rim_mm", rimJ}};
  nlohmann::json missing = nlohmann::json::object();
  if (HasTrigonum())
    j["trigonum_mm"] = trigonum;
  else
    missing["trigonum"] = trigonumMissing;
  if (HasInferiorAngle())
    j["inferior_angle_mm"] = inferiorAngle;
  else
    missing["inferior_angle"] = inferiorMissing;
  if (!rimMissing.empty())
    missing["rim"] = rimMissing;
  if (!missing.empty())
    j["not_available"] = missing;
  if (humeralHeadFound)
    j["humeral_head"] = {{"centre_mm", humeralHeadCentre}, {"radius_mm", humeralHeadRadiusMm}};
  return j;
}

GlenoidLandmarks DetectLandmarks(const SegmentedBone& bone, const LandmarkOverrides& ov,
                                 const DetectionOptions& opt) {
  GlenoidLandmarks L;
  Vec3 c, n;
  const bool placed = ov.glenoidCentre && ov.faceNormal;
  const bool fromRim = !ov.glenoidCentre && !ov.faceNormal && ov.rimPoints.size() >= 3;
  if (placed) {
    c = *ov.glenoidCentre;
    n = *ov.faceNormal;
    // The scapula: the bone of the surface point nearest the given centre.
    double best;
    std::tie(L.scapulaLabel, best) = NearestBone(bone, c);
    if (best > 10)
      throw NoGlenoidFound(
          "the given glenoid centre is " + Mm(best) +
          " from the nearest bone surface; place it on the glenoid face (where the "
          "humeral head is joined to the glenoid, the joint space may have been "
          "filled as a cavity: plan again without filling holes)");
  } else if (fromRim) {
    // Points clicked on the rim: their plane, its normal turned out of the bone.
    for (const Vec3& q : ov.rimPoints)
      if (const double dq = NearestBone(bone, q).second; !(dq <= 15)) {
        std::ostringstream m;
        m.precision(1);
        m << std::fixed << "the rim point (" << q[0] << ", " << q[1] << ", " << q[2] << ") mm is "
          << dq << " mm from the nearest bone surface; click the points on the glenoid's rim";
        throw NoGlenoidFound(m.str());
      }
    const PlaneFit plane = FitPlane(ov.rimPoints);
    if (InPlaneExtents(ov.rimPoints, plane.normal).second < 5.0)
      throw NoGlenoidFound("the given rim points lie nearly on one line (less than 5 mm across): "
                           "click three or more points around the glenoid's rim");
    double best;
    std::tie(L.scapulaLabel, best) = NearestBone(bone, plane.centroid);
    if (best > 15)
      throw NoGlenoidFound("the given rim points' centre is " + Mm(best) +
                           " from the nearest bone surface; click them on the glenoid's rim");
    n = plane.normal;
    const auto [ahead, behind] = BoneAheadAndBehind(bone, L.scapulaLabel, plane.centroid, n);
    if (ahead > behind)
      n = Scale(n, -1);
    c = plane.centroid;
  } else {
    // A centre placed with no normal, or a point clicked on the face: the joint found there, else
    // (no joint: a humeral head out of the scan or fused to the glenoid, another shoulder's
    // joint) the face's own normal around the point.
    const std::optional<Vec3> near = ov.glenoidCentre ? ov.glenoidCentre : ov.facePoint;
    std::optional<Joint> joint;
    try {
      joint = FindJoint(bone, opt);
    } catch (const NoGlenoidFound&) {
      if (!near)
        throw;
    }
    if (joint && near && Distance(joint->centre, *near) > kSameJointMm)
      joint.reset();
    if (joint) {
      L.scapulaLabel = joint->scapula;
      L.humeralHeadFound = true;
      L.humeralHeadCentre = joint->head.centre;
      L.humeralHeadRadiusMm = joint->head.radiusMm;
      c = ov.glenoidCentre ? *ov.glenoidCentre : joint->centre;
      n = ov.faceNormal ? *ov.faceNormal : joint->normal;
    } else {
      c = *near;
      double best;
      std::tie(L.scapulaLabel, best) = NearestBone(bone, c);
      if (best > 10)
        throw NoGlenoidFound(std::string(ov.glenoidCentre ? "the placed glenoid centre"
                                                          : "the point placed on the face") +
                             " is " + Mm(best) +
                             " from the nearest bone surface; click on the glenoid face");
      n = ov.faceNormal ? *ov.faceNormal : FaceNormalAround(bone, L.scapulaLabel, c);
    }
  }
  if (ov.faceNormal) {
    // A normal given the wrong way round: the scapula lies ahead of the face and not behind it.
    const auto [ahead, behind] = BoneAheadAndBehind(bone, L.scapulaLabel, c, n);
    if (ahead >= 0.5 && ahead > behind + 0.25) {
      std::ostringstream s;
      s.precision(3);
      s << std::fixed << "the given face normal (" << n[0] << ", " << n[1] << ", " << n[2]
        << ") points into the bone (" << int(std::lround(100 * ahead))
        << " % of the 12 mm ahead of the centre is scapula, " << int(std::lround(100 * behind))
        << " % behind it): the normal points out of the joint, toward the humeral head; reverse "
           "it";
      throw NoGlenoidFound(s.str());
    }
  }
  L.centreSource = ov.glenoidCentre ? "user"
                   : fromRim        ? "user rim"
                   : ov.facePoint   ? "user face point"
                                    : "detected";
  L.normalSource = ov.faceNormal ? "user"
                   : fromRim     ? "user rim"
                   : (ov.glenoidCentre || ov.facePoint) && !L.humeralHeadFound
                       ? "face around the placed point"
                       : "detected";
  // Rim, plane and centre around the axis.
  std::vector<Vec3> cands;
  std::vector<Vec3> candNormals;
  for (const auto& sp : bone.Surface())
    if (sp.label == L.scapulaLabel && Distance(sp.p, c) <= opt.rimSearchRadiusMm + 15 &&
        Dot(Sub(sp.p, c), n) >= -12)
      cands.push_back(sp.p), candNormals.push_back(sp.normal);
  if (cands.size() < size_t(opt.rimPoints)) {
    if (!placed)
      throw NoGlenoidFound("no glenoid found: no glenoid surface around the joint" +
                           std::string(kPlaceHint));
    L.rimMissing = "too few bone surface points (" + std::to_string(cands.size()) +
                   ") around the given centre to trace the rim";
  }
  for (int it = 0; it < kRimIterations && L.rimMissing.empty(); ++it) {
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
  L.side = L.faceNormal[0] > 0 ? "left" : "right";
  // The face: inside 80 % of the rim's radius in the rim's direction (12 mm without a rim),
  // facing out of the joint.
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
      double rr = 15, bestA = 10;
      for (const auto& [a, r] : rimPolar) {
        const double da = std::abs(std::remainder(a - ang, 2 * 3.14159265358979323846));
        if (da < bestA)
          bestA = da, rr = r;
      }
      if (std::hypot(u, v) <= 0.8 * rr && Dot(candNormals[i], n) > 0.5 && Dot(d, n) >= -10)
        L.face.push_back(cands[i]);
    }
  }
  // Scapular-plane landmarks: each found, given, or not available with its reason. A landmark
  // whose tip (the bone's farthest voxel) lies within a scan voxel of the scan's edge is where
  // the bone leaves the field of view (a voxel cut by the edge has its centre half a voxel in).
  const double reach = std::max(bone.Spacing(), opt.scanSpacingMm);
  if (ov.trigonum) {
    L.trigonum = *ov.trigonum;
    L.trigonumSource = "user";
  } else if (const SpineRootResult spine = FindSpineRoot(bone, L.scapulaLabel, c); spine.root) {
    // The root of the spine, found in the scapula's own frame.
    L.trigonum = spine.root->trigonum;
    L.trigonumSource = "detected: root of the scapular spine";
    const std::string edge = NearScanEdge(opt.scanBounds, L.trigonum, reach, {true, true, true});
    if (!edge.empty())
      L.trigonumMissing = "the scapula leaves the scan at its " + edge +
                          " edge along the scapular spine (the medial border is outside the "
                          "field of view)";
  } else {
    const double kf = (c[2] - bone.Origin()[2]) / bone.Spacing();
    const int k0 = int(std::floor(kf));
    const double t = kf - k0;
    const auto a = FarthestEnd(bone, L.scapulaLabel, c, k0, 3.0);
    const auto b = FarthestEnd(bone, L.scapulaLabel, c, k0 + 1, 3.0);
    L.trigonumSource =
        "detected: medial tip on the glenoid centre's axial plane (" + spine.reason + ")";
    if (!a || !b)
      L.trigonumMissing = "the scapula does not reach the glenoid centre's axial plane";
    else
      L.trigonum = Add(Scale(a->centroid, 1 - t), Scale(b->centroid, t));
    const std::string edge =
        L.HasTrigonum()
            ? NearScanEdge(opt.scanBounds, t < 0.5 ? a->tip : b->tip, reach, {true, true, false})
            : "";
    if (!edge.empty())
      L.trigonumMissing = "the scapula leaves the scan at its " + edge +
                          " edge on the glenoid centre's axial plane (the medial border is "
                          "outside the field of view)";
  }
  if (L.HasTrigonum() && Distance(L.trigonum, c) < 50)
    L.trigonumMissing = "the scapula ends " + Mm(Distance(L.trigonum, c)) +
                        " medial of the glenoid centre on its axial plane (a scapular body "
                        "reaches >= 50 mm): the medial border is outside the scan or the scapula "
                        "is turned out of the axial plane";
  if (ov.inferiorAngle) {
    L.inferiorAngle = *ov.inferiorAngle;
    L.inferiorSource = "user";
  } else {
    const auto a = FarthestEnd(bone, L.scapulaLabel, c, -1, 5.0, c[2] - 20.0);
    L.inferiorSource = "detected";
    if (!a)
      L.inferiorMissing = "no scapula bone 20 mm or more below the glenoid centre";
    else
      L.inferiorAngle = a->centroid;
    const std::string edge =
        L.HasInferiorAngle() ? NearScanEdge(opt.scanBounds, a->tip, reach, {true, true, true}) : "";
    if (!edge.empty())
      L.inferiorMissing = "the scapula leaves the scan at its " + edge +
                          " edge (the inferior angle is outside the field of view)";
  }
  if (L.HasInferiorAngle() && Distance(L.inferiorAngle, c) < 50)
    L.inferiorMissing = "the scapula reaches only " + Mm(Distance(L.inferiorAngle, c)) +
                        " from the glenoid centre (>= 50 mm expected): the CT may not hold the "
                        "whole scapula";
  if (!L.HasTrigonum())
    L.trigonumSource = "not available";
  if (!L.HasInferiorAngle())
    L.inferiorSource = "not available";
  return L;
}

} // namespace bm
