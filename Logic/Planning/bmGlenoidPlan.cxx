#include "bmGlenoidPlan.h"

#include "bmToolModel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace bm {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
std::string Fixed(double v, int digits = 1) {
  std::ostringstream s;
  s.precision(digits);
  s << std::fixed << v;
  return s.str();
}
} // namespace

void PlanOptions::Validate() const {
  auto need = [](bool ok, const std::string& what) {
    if (!ok)
      throw std::invalid_argument("plan: " + what);
  };
  need(std::abs(targetVersionDeg) < 45, "target version must be within (-45, 45) deg");
  need(std::abs(targetInclinationDeg) < 45, "target inclination must be within (-45, 45) deg");
  need(reamerDiameterMm > 10 && reamerDiameterMm <= 60, "reamer diameter must be in (10, 60] mm");
  need(reamDepthMm > 0 && reamDepthMm <= 10, "reaming depth must be in (0, 10] mm");
  const ArcLipParams reamer;
  need(pinRadiusMm > reamer.nippleRadius && pinRadiusMm <= 5,
       "guide-pin radius must exceed the reamer nipple's " + Fixed(reamer.nippleRadius) +
           " mm and be <= 5 mm");
  need(pinDepthMm == 0 || (pinDepthMm > 0 && pinDepthMm <= 40),
       "guide-pin depth must be 0 (automatic) or in (0, 40] mm");
  need(pinFeedMmPerRev > 0 && pinSpeedRpm > 0 && reamFeedMmPerRev > 0 && reamSpeedRpm > 0,
       "feeds (mm/rev) and speeds (rpm) must be > 0");
  need(voxmapResolution >= 8 && voxmapResolution <= 4096 && shellResolution >= 8 &&
           shellResolution <= 4096,
       "resolutions must be in [8, 4096] cells");
  need(roiHalfMm > 5 && roiHalfMm <= 100, "the bone region's half size must be in (5, 100] mm");
}

GlenoidPlan MakeGlenoidPlan(const GlenoidLandmarks& L, const GlenoidMeasurements& m,
                            const PlanOptions& opt) {
  opt.Validate();
  GlenoidPlan p;
  p.options = opt;
  p.entry = L.glenoidCentre;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (m.hasFrame) {
    p.axis = DirectionFromAngles(m.frame, opt.targetVersionDeg, opt.targetInclinationDeg);
    p.corrected = true;
    p.axisVersionDeg = Version3DDeg(m.frame, p.axis);
    p.axisInclinationDeg = InclinationDeg(m.frame, p.axis);
  } else {
    p.axis = L.faceNormal;
    p.axisVersionDeg = p.axisInclinationDeg = nan;
    const auto why = m.notAvailable.find("version_3d_deg");
    p.warnings.push_back(
        "no correction: the axis is the face normal as " +
        std::string(L.normalSource == "detected" ? "found" : "placed") + ", since " +
        (why != m.notAvailable.end() ? why->second : std::string("there is no scapular plane")) +
        "; place the trigonum and the inferior angle to correct version and inclination");
  }
  p.correctionDeg = AngleDeg(L.faceNormal, p.axis);
  const ArcLipParams reamer;
  p.pinDepthMm = opt.pinDepthMm > 0 ? opt.pinDepthMm : opt.reamDepthMm + reamer.nippleLength + 2;
  if (p.pinDepthMm < opt.reamDepthMm + reamer.nippleLength)
    p.warnings.push_back("the guide-pin hole (" + Fixed(p.pinDepthMm) +
                         " mm) is shallower than the reamer's nipple reaches (" +
                         Fixed(opt.reamDepthMm + reamer.nippleLength) +
                         " mm): the nipple will meet solid bone");
  // The tool starts 1 mm above the highest rim point (the face's points without a rim).
  double rimTop = 0;
  for (const auto& q : L.rim.empty() ? L.face : L.rim)
    rimTop = std::max(rimTop, Dot(Sub(q, p.entry), p.axis));
  p.clearanceMm = rimTop + 1.0;
  const bool sized = std::isfinite(m.widthMm) && std::isfinite(m.heightMm);
  p.reamerOverhangApMm = sized ? std::max(0.0, 0.5 * (opt.reamerDiameterMm - m.widthMm)) : nan;
  p.reamerOverhangSiMm = sized ? std::max(0.0, 0.5 * (opt.reamerDiameterMm - m.heightMm)) : nan;
  p.reamerFits = sized && p.reamerOverhangApMm == 0 && p.reamerOverhangSiMm == 0;
  if (!sized)
    p.warnings.push_back("the reamer's size is not checked: the glenoid's rim is not available (" +
                         L.rimMissing + ")");
  else if (!p.reamerFits)
    p.warnings.push_back("the " + Fixed(opt.reamerDiameterMm) + " mm reamer overhangs the " +
                         Fixed(m.heightMm) + " x " + Fixed(m.widthMm) + " mm glenoid by " +
                         Fixed(p.reamerOverhangApMm) + " mm anteriorly and posteriorly and " +
                         Fixed(p.reamerOverhangSiMm) + " mm superiorly and inferiorly");
  // Plausibility: arthritic glenoids lie within about -30..+15 deg of version and -15..+30 deg
  // of inclination (Docs/Planning.md); beyond +-30 deg a landmark is more likely misplaced.
  auto flag = [&](const std::string& what, const std::string& advice = "") {
    p.implausible.push_back(what);
    p.warnings.push_back("check the landmarks: " + what + advice);
  };
  if (std::abs(m.version3DDeg) > 30)
    flag("3D version " + Fixed(m.version3DDeg) + " deg is beyond +-30 deg");
  if (std::abs(m.friedmanVersionDeg) > 30)
    flag("Friedman version " + Fixed(m.friedmanVersionDeg) + " deg is beyond +-30 deg");
  if (std::abs(m.inclinationDeg) > 30)
    flag("inclination " + Fixed(m.inclinationDeg) + " deg is beyond +-30 deg");
  if (p.correctionDeg > 15)
    flag("the correction of " + Fixed(p.correctionDeg) + " deg is beyond 15 deg",
         "; if it is real, reaming alone removes much bone from the face's high side and "
         "medialises the joint line: consider an augmented implant");
  return p;
}

nlohmann::json GlenoidPlan::CtBoneJson(const std::string& ctPath) const {
  return CtBoneJsonWithSettings(nlohmann::json{{"ct", ctPath}});
}

nlohmann::json GlenoidPlan::CtBoneJsonWithSettings(const nlohmann::json& importSettings) const {
  if (!importSettings.is_object() || !importSettings.contains("ct") ||
      !importSettings["ct"].is_string() || importSettings["ct"].get<std::string>().empty())
    throw std::invalid_argument("plan: the CT's import settings name no CT (\"ct\")");
  nlohmann::json ct = importSettings;
  for (const char* k : {"roi", "box", "seed", "resolution", "keepAllComponents"})
    ct.erase(k);
  const Vec3 seed = AddScaled(entry, axis, -1.0);
  const double h = options.roiHalfMm;
  ct["seed"] = seed;
  ct["roi"] = {entry[0] - h, entry[1] - h, entry[2] - h, entry[0] + h, entry[1] + h, entry[2] + h};
  return {{"type", "ct"}, {"ct", ct}};
}

nlohmann::json GlenoidPlan::StepSceneJson(int i, const nlohmann::json& bone) const {
  if (i != 0 && i != 1)
    throw std::invalid_argument("plan: step must be 0 (guide pin) or 1 (ream)");
  const double pinClearance = 1.0 +
                              options.pinRadiusMm * std::tan(std::min(correctionDeg, 60.0) * kDeg) +
                              options.pinRadiusMm * options.pinRadiusMm / 20.0;
  nlohmann::json s;
  if (i == 0) {
    s = {{"name", "guide pin"},
         {"description", "Guide-pin hole along the planned axis, " + Fixed(pinDepthMm) +
                             " mm deep, for the reamer's nipple"},
         {"tool",
          {{"type", "drill"},
           {"radius_mm", options.pinRadiusMm},
           {"flute_length_mm", pinDepthMm + 5}}},
         {"trial",
          {{"feed_mm_per_rev", options.pinFeedMmPerRev},
           {"speed_rpm", options.pinSpeedRpm},
           {"entry_mm", entry},
           {"axis", axis},
           {"clearance_mm", pinClearance},
           {"depth_mm", pinDepthMm}}}};
  } else {
    s = {{"name", "ream"},
         {"description", "Nipple-guided reaming along the planned axis to " +
                             Fixed(options.reamDepthMm) + " mm below the glenoid centre"},
         {"tool", {{"type", "reamer"}}},
         {"trial",
          {{"feed_mm_per_rev", options.reamFeedMmPerRev},
           {"speed_rpm", options.reamSpeedRpm},
           {"entry_mm", entry},
           {"axis", axis},
           {"clearance_mm", clearanceMm},
           {"depth_mm", options.reamDepthMm}}}};
  }
  s["bone"] = bone;
  s["voxmap_resolution"] = options.voxmapResolution;
  s["shell_resolution"] = options.shellResolution;
  s["method"] = "lazar";
  return s;
}

nlohmann::json GlenoidPlan::SceneJson(const nlohmann::json& bone) const {
  nlohmann::json steps = nlohmann::json::array();
  for (int i = 0; i < 2; ++i) {
    nlohmann::json s = StepSceneJson(i, bone);
    steps.push_back({{"name", s["name"]},
                     {"description", s["description"]},
                     {"tool", s["tool"]},
                     {"trial", s["trial"]}});
  }
  return {{"name", "glenoid plan"},
          {"description",
           "Guide pin, then nipple-guided reaming, on the same bone, along the planned axis (" +
               (corrected ? "version " + Fixed(axisVersionDeg) + " deg, inclination " +
                                Fixed(axisInclinationDeg) + " deg"
                          : std::string("the face normal, not corrected")) +
               ")"},
          {"bone", bone},
          {"steps", steps},
          {"voxmap_resolution", options.voxmapResolution},
          {"shell_resolution", options.shellResolution},
          {"method", "lazar"},
          {"planning", ToJson()}};
}

void CheckToolStartsOutsideBone(const SegmentedBone& bone, const GlenoidLandmarks& L,
                                const GlenoidPlan& p) {
  const double radius = 0.5 * p.options.reamerDiameterMm, h = bone.Spacing();
  // From the highest a glenoid's rim can rise above its centre along the axis (6 mm of
  // concavity and the face's tilt to the axis over the reamer's radius), or the start when it is
  // lower, to 20 mm beyond: a rim found on a joined head would put the start beyond the head.
  const double rimBound = 6.0 + radius * std::tan(std::min(p.correctionDeg, 60.0) * kDeg);
  const double lo = std::min(p.clearanceMm, rimBound), hi = lo + 20.0;
  // The box around the cylinder, then each voxel's centre against it.
  Vec3 boxLo, boxHi;
  for (size_t a = 0; a < 3; ++a) {
    const double e = radius + 1.0;
    const double c0 = p.entry[a] + lo * p.axis[a], c1 = p.entry[a] + hi * p.axis[a];
    boxLo[a] = std::min(c0, c1) - e;
    boxHi[a] = std::max(c0, c1) + e;
  }
  const auto& d = bone.Dims();
  int i0[3], i1[3];
  for (int a = 0; a < 3; ++a) {
    i0[a] = std::max(0, int(std::floor((boxLo[size_t(a)] - bone.Origin()[size_t(a)]) / h)));
    i1[a] = std::min(d[size_t(a)] - 1,
                     int(std::ceil((boxHi[size_t(a)] - bone.Origin()[size_t(a)]) / h)));
  }
  double volume = 0;
  Vec3 sum{0, 0, 0};
  for (int k = i0[2]; k <= i1[2]; ++k)
    for (int j = i0[1]; j <= i1[1]; ++j)
      for (int i = i0[0]; i <= i1[0]; ++i) {
        const int64_t idx = bone.Index(i, j, k);
        if (bone.Label(idx) != L.scapulaLabel)
          continue;
        const Vec3 q = Sub(bone.Centre(i, j, k), p.entry);
        const double t = Dot(q, p.axis);
        if (t < lo || t > hi || Norm(AddScaled(q, p.axis, -t)) > radius)
          continue;
        const double v = bone.Fraction(idx) * h * h * h;
        volume += v;
        sum = AddScaled(sum, bone.Centre(i, j, k), v);
      }
  if (volume <= h * h * h)
    return;
  const Vec3 at = Scale(sum, 1.0 / volume);
  throw PlanBlocked("the reamer would start inside bone: " + Fixed(volume) +
                    " mm^3 of bone joined "
                    "to the scapula lies in its path beyond the face, around (" +
                    Fixed(at[0]) + ", " + Fixed(at[1]) + ", " + Fixed(at[2]) +
                    ") mm (a humeral head joined to the glenoid at this threshold?): give an "
                    "exclude point on that bone (--exclude), a higher threshold, or a region "
                    "without it");
}

PlanScenes MakePlanScenes(const GlenoidLandmarks& L, const GlenoidMeasurements& m,
                          const GlenoidPlan& plan, const nlohmann::json& importSettings) {
  const nlohmann::json bone = plan.CtBoneJsonWithSettings(importSettings);
  PlanScenes s{plan.SceneJson(bone), plan.StepSceneJson(0, bone), plan.StepSceneJson(1, bone)};
  s.plan["planning"] = PlanningJson(L, m, plan);
  return s;
}

nlohmann::json PlanningJson(const GlenoidLandmarks& L, const GlenoidMeasurements& m,
                            const GlenoidPlan& plan) {
  nlohmann::json j = plan.ToJson();
  j["landmarks"] = L.ToJson();
  j["measurements"] = m.ToJson();
  return j;
}

nlohmann::json GlenoidPlan::ToJson() const {
  auto value = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"target_version_deg", options.targetVersionDeg},
          {"target_inclination_deg", options.targetInclinationDeg},
          {"entry_mm", entry},
          {"axis", axis},
          {"correction_deg", correctionDeg},
          {"corrected", corrected},
          {"axis_version_deg", value(axisVersionDeg)},
          {"axis_inclination_deg", value(axisInclinationDeg)},
          {"ream_depth_mm", options.reamDepthMm},
          {"pin_radius_mm", options.pinRadiusMm},
          {"pin_depth_mm", pinDepthMm},
          {"reamer_diameter_mm", options.reamerDiameterMm},
          {"reamer_fits", reamerFits},
          {"reamer_overhang_ap_mm", value(reamerOverhangApMm)},
          {"reamer_overhang_si_mm", value(reamerOverhangSiMm)},
          {"clearance_mm", clearanceMm},
          {"warnings", warnings},
          {"implausible", implausible}};
}

} // namespace bm
