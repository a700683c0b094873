// bmsim plan - glenoid planning on a shoulder CT or the scapula phantom: segment, find the
// glenoid and the scapular landmarks, measure version and inclination, propose the reaming axis,
// write the plan scene (guide pin, then ream) and the pre-operative report (Docs/Planning.md).
// Also `bmsim phantom scapula` (called from bmsimPhantom.cxx).
#include "bmsimArgs.h"
#include "bmsimCommand.h"

#ifdef BM_PLANNING_WITH_IO // the plan reads a CT: built only with CT import
#include "bmAtomicFile.h"
#include "bmGlenoidLandmarks.h"
#include "bmGlenoidMeasurements.h"
#include "bmGlenoidPlan.h"
#include "bmImport.h"
#include "bmPlanReport.h"
#include "bmScapulaCT.h"
#include "bmSegmentedBone.h"
#include "bmJson.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

void RequireEmptyOut(const std::string& out) {
  if (out.empty())
    throw bm::cli::UsageError("--out DIR is required");
  if (fs::is_directory(out))
    bm::RemoveStaleTemporaries(out); // what a killed run left does not block this one
  if (fs::exists(out) && (!fs::is_directory(out) || !fs::is_empty(out)))
    throw std::runtime_error("--out " + out + " exists and is not an empty folder");
}

std::string Fx(double v, int d = 1) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(d) << v;
  return s.str();
}

} // namespace

namespace bm::cli {

ProgressFn TerminalProgress(bool quiet); // bmsimImport.cxx

int ScapulaPhantomCommand(const ParsedArgs& p) {
  if (p.Positional().size() != 1 || p.Positional()[0] != "scapula")
    throw UsageError("name one phantom: scapula");
  ScapulaPhantomParams sp = p.Has("b2") ? ScapulaPhantomParams::B2() : ScapulaPhantomParams{};
  sp.versionDeg = p.GetDouble("version", -45, 45).value_or(sp.versionDeg);
  sp.inclinationDeg = p.GetDouble("inclination", -45, 45).value_or(sp.inclinationDeg);
  if (p.Has("left")) {
    sp.rightSide = false;
    sp.glenoidCentreMm[0] = -sp.glenoidCentreMm[0];
  }
  PhantomCTOptions ct = ScapulaCTDefaults();
  ct.noiseHU = p.GetDouble("noise", 0, 1000).value_or(ct.noiseHU);
  DicomWriteOptions dicom;
  if (const auto syntax = p.Get("compress")) {
    dicom.transferSyntax = *syntax;
    if (*syntax != "rle" && *syntax != "jpeg-lossless" && *syntax != "jpeg-ls" &&
        *syntax != "jpeg2000")
      throw UsageError("--compress must be rle, jpeg-lossless, jpeg-ls or jpeg2000");
  }
  const std::string out = p.Get("out", "");
  RequireEmptyOut(out);
  const ScapulaPhantom ph(sp);
  const bool quiet = p.Has("quiet");
  WriteScapulaSeries(ph, out, ct, dicom, Progress(TerminalProgress(quiet)));
  if (!quiet && isatty(2))
    std::fprintf(stderr, "\n");
  const ScapulaTruth& t = ph.Truth();
  const auto& c = t.glenoidCentre;
  const auto& n = t.faceNormal;
  std::cout << "phantom:     scapula (" << (sp.rightSide ? "right" : "left")
            << " shoulder, DICOM series, CT)" << (sp.wearDepthMm > 0 ? ", B2 posterior wear" : "")
            << "\nwrote:       " << out << " and " << (fs::path(out) / "truth.json").string()
            << "\nglenoid:     centre (" << Fx(c[0], 2) << ", " << Fx(c[1], 2) << ", "
            << Fx(c[2], 2) << ") mm, face normal (" << Fx(n[0], 4) << ", " << Fx(n[1], 4) << ", "
            << Fx(n[2], 4) << ")\n"
            << "truth:       3D version " << Fx(t.version3DDeg, 2) << " deg, Friedman version "
            << Fx(t.friedmanVersionDeg, 2) << " deg, inclination " << Fx(t.inclinationDeg, 2)
            << " deg, height " << Fx(t.glenoidHeightMm) << " mm, width " << Fx(t.glenoidWidthMm)
            << " mm\n";
  return 0;
}

static void PlanCommandOptions(ParsedArgs& p) {
  p.Words("CT|phantom", "DICOM folder, volume file or .inv3 project holding the shoulder, or "
                        "'phantom': the scapula phantom (its DICOM series is written to DIR/ct "
                        "first)")
      .Value("o,out", "DIR",
             "folder to create (must not exist or be empty; required); receives plan.json (both "
             "steps), step1-guide-pin.json, step2-ream.json (single-step scenes for bmsim run), "
             "plan_report.md/.html/.json")
      .Value("landmarks", "FILE",
             "landmarks replacing detected ones: a plan.json (its edited planning.landmarks) or "
             "a JSON object of glenoid_centre_mm, face_normal, trigonum_mm, inferior_angle_mm "
             "(world mm, LPS)")
      .Real("target-version", -44.9, 44.9, "DEG", "target version of the reaming axis (default 0)")
      .Real("target-inclination", -44.9, 44.9, "DEG", "target inclination (default 0)")
      .Real("reamer-diameter", 10, 60, "MM",
            "reamer size checked against the glenoid (default 36.5)")
      .Real("ream-depth", 0.01, 10, "MM", "reaming depth below the glenoid centre (default 2)")
      .Real("pin-radius", 0.01, 5, "MM",
            "guide-pin hole radius (default 3.2; above the nipple's 3)")
      .Real("pin-depth", 0.01, 40, "MM", "guide-pin depth (default: ream depth + nipple 6 + 2 mm)")
      .Int("resolution", 32, 1024,
           "voxmap cells along the bone's longest side for detection (default 256)")
      .Real("threshold", -1000, 4000, "HU", "bone threshold (default 200)")
      .Real("phantom-version", -45, 45, "DEG", "phantom: its glenoid version (default -12)")
      .Real("phantom-inclination", -45, 45, "DEG", "phantom: its inclination (default 8)")
      .Flag("b2", "phantom: posterior wear (a biconcave Walch B2 face)")
      .Flag("q,quiet", "no progress bar")
      .Footer("Exit status 3: no glenoid found; the report says why and lists the landmarks to "
              "place.");
}

static int PlanCommand(const ParsedArgs& p) {
  if (p.Positional().size() != 1)
    throw UsageError("name one CT (or phantom)");
  const std::string input = p.Positional()[0];
  const bool phantom = input == "phantom";
  PlanOptions po;
  po.targetVersionDeg = p.GetDouble("target-version", -44.9, 44.9).value_or(0.0);
  po.targetInclinationDeg = p.GetDouble("target-inclination", -44.9, 44.9).value_or(0.0);
  po.reamerDiameterMm = p.GetDouble("reamer-diameter", 10, 60).value_or(po.reamerDiameterMm);
  po.reamDepthMm = p.GetDouble("ream-depth", 0.01, 10).value_or(po.reamDepthMm);
  po.pinRadiusMm = p.GetDouble("pin-radius", 0.01, 5).value_or(po.pinRadiusMm);
  po.pinDepthMm = p.GetDouble("pin-depth", 0.01, 40).value_or(0.0);
  try {
    po.Validate();
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  ImportOptions io;
  io.resolution = int(p.GetInt("resolution", 32, 1024).value_or(256));
  io.segmentation.thresholdHU = float(p.GetDouble("threshold", -1000, 4000).value_or(200));
  io.segmentation.keepAllComponents = true; // the humeral head shows where the glenoid is
  LandmarkOverrides ov;
  if (const auto f = p.Get("landmarks")) {
    std::error_code ec;
    if (std::filesystem::exists(*f, ec) && !std::filesystem::is_regular_file(*f, ec))
      throw std::runtime_error("the landmarks file " + *f +
                               " is not a regular file (a FIFO would block the read)");
    std::ifstream in(*f);
    if (!in)
      throw std::runtime_error("cannot read the landmarks file " + *f);
    nlohmann::json j;
    try {
      j = bm::ParseJson(in, "landmarks file " + *f); // at most kMaxJsonDepth levels
    } catch (const std::exception& e) {
      throw std::runtime_error("landmarks file " + *f + " is not JSON: " + e.what());
    }
    // A plan.json (its "planning"."landmarks"), {"landmarks": {...}} or the landmarks alone.
    const nlohmann::json& lj = j.contains("planning") && j["planning"].contains("landmarks")
                                   ? j["planning"]["landmarks"]
                               : j.contains("landmarks") ? j["landmarks"]
                                                         : j;
    ov = LandmarkOverrides::FromJson(lj);
  }
  ScapulaPhantomParams sp = p.Has("b2") ? ScapulaPhantomParams::B2() : ScapulaPhantomParams{};
  sp.versionDeg = p.GetDouble("phantom-version", -45, 45).value_or(sp.versionDeg);
  sp.inclinationDeg = p.GetDouble("phantom-inclination", -45, 45).value_or(sp.inclinationDeg);
  if (!phantom && (p.Has("b2") || p.Has("phantom-version") || p.Has("phantom-inclination")))
    throw UsageError("--b2, --phantom-version and --phantom-inclination apply to the phantom");
  if (!phantom && !fs::exists(input))
    throw std::runtime_error("CT " + input + " does not exist");
  const std::string out = p.Get("out", "");
  RequireEmptyOut(out);
  const bool quiet = p.Has("quiet");
  const Progress progress(TerminalProgress(quiet));

  std::string ctPath, ctRef, source;
  nlohmann::json truth;
  // A failure before the plan's outputs leaves nothing behind: the folder when made here, else
  // (RequireEmptyOut: it was empty) the phantom's CT written into it. The CT keeps a temporary's
  // name (".ct.tmp-PID-N") until the plan is written: a killed run leaves only that, which the
  // next run removes (RequireEmptyOut), not a DIR/ct that would block it.
  struct Cleanup {
    fs::path dir, ct;
    bool created;
    bool armed = true;
    ~Cleanup() {
      std::error_code ec;
      if (armed)
        fs::remove_all(created ? dir : ct, ec);
    }
  } cleanup{out, fs::path(out) / "ct", !fs::exists(out)};
  fs::create_directories(out);
  std::string stagedCT;
  const auto placeCT = [&] {
    if (!stagedCT.empty())
      fs::rename(stagedCT, fs::path(out) / "ct");
    stagedCT.clear();
  };
  if (phantom) {
    const ScapulaPhantom ph(sp);
    stagedCT = TemporarySibling((fs::path(out) / "ct").string());
    cleanup.ct = stagedCT;
    ctPath = stagedCT;
    WriteScapulaSeries(ph, ctPath, ScapulaCTDefaults(), {}, progress.Range(0, 0.3));
    ctRef = fs::absolute(fs::path(out) / "ct").string();
    truth = ScapulaTruthJson(ph);
    source = (fs::path(out) / "ct").string() + " (scapula phantom, version " + Fx(sp.versionDeg) +
             " deg, inclination " + Fx(sp.inclinationDeg) + " deg" +
             (sp.wearDepthMm > 0 ? ", B2" : "") + ")";
  } else {
    ctPath = input;
    ctRef = fs::absolute(input).string();
    source = ctRef;
  }
  ImportResult r = ImportVoxmap(ctPath, io, progress.Range(phantom ? 0.3 : 0, 0.9));
  if (phantom)
    r.source = (fs::path(out) / "ct").string(); // where it is once the plan is written
  cleanup.armed = false;
  progress(0.95, "finding the glenoid");
  PlanReportInput rep;
  rep.source = source;
  rep.importSummary = r.Report();
  rep.truth = truth;
  const SegmentedBone bone(r.voxmap);
  GlenoidLandmarks L;
  GlenoidMeasurements m;
  GlenoidPlan plan;
  try {
    L = DetectLandmarks(bone, ov);
    m = MeasureGlenoid(L);
    plan = MakeGlenoidPlan(L, m, po);
  } catch (const NoGlenoidFound& e) {
    rep.failure = e.what();
    placeCT();
    WriteFilesAtomic(
        {{(fs::path(out) / "plan_report.md").string(), PlanReportMarkdown(rep)},
         {(fs::path(out) / "plan_report.html").string(), PlanReportHtml(rep)},
         {(fs::path(out) / "plan_report.json").string(), PlanReportJson(rep).dump(2) + "\n"}});
    if (!quiet && isatty(2))
      std::fprintf(stderr, "\n");
    std::cerr << "bmsim plan: " << e.what() << "\nwrote " << (fs::path(out) / "plan_report.md")
              << " (no plan)\n";
    return 3;
  }
  rep.landmarks = &L;
  rep.measurements = &m;
  rep.plan = &plan;
  const nlohmann::json boneJ = plan.CtBoneJson(ctRef);
  nlohmann::json planScene = plan.SceneJson(boneJ);
  planScene["planning"]["landmarks"] = L.ToJson(); // edit and plan again with --landmarks
  planScene["planning"]["measurements"] = m.ToJson();
  placeCT();
  WriteFilesAtomic(
      {{(fs::path(out) / "plan.json").string(), planScene.dump(2) + "\n"},
       {(fs::path(out) / "step1-guide-pin.json").string(),
        plan.StepSceneJson(0, boneJ).dump(2) + "\n"},
       {(fs::path(out) / "step2-ream.json").string(), plan.StepSceneJson(1, boneJ).dump(2) + "\n"},
       {(fs::path(out) / "plan_report.md").string(), PlanReportMarkdown(rep)},
       {(fs::path(out) / "plan_report.html").string(), PlanReportHtml(rep)},
       {(fs::path(out) / "plan_report.json").string(), PlanReportJson(rep).dump(2) + "\n"}});
  progress(1.0, "planned");
  if (!quiet && isatty(2))
    std::fprintf(stderr, "\n");
  const auto& c = L.glenoidCentre;
  const auto& a = plan.axis;
  std::cout << "CT:            " << source << "\n"
            << "glenoid:       centre (" << Fx(c[0]) << ", " << Fx(c[1]) << ", " << Fx(c[2])
            << ") mm (" << L.centreSource << "), " << Fx(m.heightMm) << " x " << Fx(m.widthMm)
            << " mm, radius of curvature " << Fx(m.faceRadiusMm) << " mm\n"
            << "version:       " << Fx(m.friedmanVersionDeg) << " deg (Friedman 2D), "
            << Fx(m.version3DDeg) << " deg (3D)\n"
            << "inclination:   " << Fx(m.inclinationDeg) << " deg (3D)\n"
            << "axis:          (" << Fx(a[0], 4) << ", " << Fx(a[1], 4) << ", " << Fx(a[2], 4)
            << "): version " << Fx(plan.axisVersionDeg) << " deg, inclination "
            << Fx(plan.axisInclinationDeg) << " deg, correction " << Fx(plan.correctionDeg)
            << " deg\n"
            << "reamer:        " << Fx(po.reamerDiameterMm) << " mm, "
            << (plan.reamerFits ? "within the glenoid" : "overhangs the glenoid") << "\n";
  for (const auto& w : plan.warnings)
    std::cout << "warning:       " << w << "\n";
  std::cout << "wrote:         " << out << "/plan.json, step1-guide-pin.json, step2-ream.json, "
            << "plan_report.md/.html/.json\n";
  return 0;
}

BM_REGISTER_COMMAND(plan, "plan glenoid reaming on a shoulder CT (or the scapula phantom)",
                    PlanCommandOptions, PlanCommand);

} // namespace bm::cli
#endif
