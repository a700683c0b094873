// bmsim plan - glenoid planning on a shoulder CT or the scapula phantom: segment, find the
// glenoid and the scapular landmarks, measure version and inclination, propose the reaming axis,
// write the plan scene (guide pin, then ream) and the pre-operative report (Docs/Planning.md).
// Also `bmsim phantom scapula` (called from bmsimPhantom.cxx).
#include "bmsimArgs.h"
#include "bmsimCommand.h"

#ifdef BM_PLANNING_WITH_IO // the plan reads a CT: built only with CT import
#include "bmsimCTOptions.h"
#include "bmAtomicFile.h"
#include "bmGlenoidLandmarks.h"
#include "bmJoinedHeadCut.h"
#include "bmGlenoidMeasurements.h"
#include "bmGlenoidPlan.h"
#include "bmImport.h"
#include "bmPlanFiles.h"
#ifdef BM_WITH_REPORT
#include "bmFailurePicture.h"
#endif
#include "bmScapulaCT.h"
#include "bmStoredAxes.h"
#include "bmWindowedVolume.h"
#include "bmSegmentedBone.h"
#include "bmJson.h"
#ifdef BM_WITH_DCMTK
#include "bmPacsClient.h"
#endif

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
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

/// A value and its unit, or "not available" where it is NaN (a measurement the landmarks do not
/// allow).
std::string Na(double v, const char* unit) {
  return std::isfinite(v) ? Fx(v) + " " + unit : std::string("not available");
}

} // namespace

namespace bm::cli {

/// The landmarks with no side named: detection on each side. Both found: the plan stops
/// (NoGlenoidFound: the report) naming both; one found: its landmarks; none: the detection on
/// either side, whose failure names every rejected pair.
static GlenoidLandmarks DetectOneShoulder(const SegmentedBone& bone, const LandmarkOverrides& ov,
                                          const DetectionOptions& detect) {
  std::optional<GlenoidLandmarks> found[2];
  const ShoulderSide sides[2] = {ShoulderSide::Left, ShoulderSide::Right};
  for (int i = 0; i < 2; ++i) {
    DetectionOptions d = detect;
    d.side = sides[i];
    try {
      found[i] = DetectLandmarks(bone, ov, d);
    } catch (const NoGlenoidFound&) {
    }
  }
  if (found[0] && found[1]) {
    const Vec3 &l = found[0]->glenoidCentre, &r = found[1]->glenoidCentre;
    throw NoGlenoidFound("both shoulders are in the scan (a left glenoid at (" + Fx(l[0]) + ", " +
                             Fx(l[1]) + ", " + Fx(l[2]) + ") mm, a right one at (" + Fx(r[0]) +
                             ", " + Fx(r[1]) + ", " + Fx(r[2]) +
                             ") mm): choose one with --side left|right",
                         {l, r});
  }
  if (found[0] || found[1])
    return found[0] ? *found[0] : *found[1];
  return DetectLandmarks(bone, ov, detect);
}

ProgressFn TerminalProgress(bool quiet); // bmsimImport.cxx

int ScapulaPhantomCommand(const ParsedArgs& p) {
  if (p.Positional().size() != 1 || p.Positional()[0] != "scapula")
    throw UsageError("name one phantom: scapula");
  ScapulaPhantomParams sp = p.Has("b2") ? ScapulaPhantomParams::B2() : ScapulaPhantomParams{};
  sp.versionDeg = p.GetDouble("version", -45, 45).value_or(sp.versionDeg);
  sp.inclinationDeg = p.GetDouble("inclination", -45, 45).value_or(sp.inclinationDeg);
  sp.jointGapMm = p.GetDouble("joint-gap", 1, 20).value_or(sp.jointGapMm);
  sp.spine = p.Has("spine");
  sp.armRaised = p.Has("arm-raised");
  sp.humerus = p.Has("humerus") || sp.armRaised;
  sp.cancellousHU = float(p.GetDouble("cancellous-hu", -1000, 3000).value_or(sp.cancellousHU));
  if (const auto r = p.GetDoubles("rotate", 3)) {
    for (double a : *r)
      if (!(std::abs(a) <= 45))
        throw UsageError("--rotate: each angle must be within [-45, 45] deg");
    sp.patientRotationDeg = {(*r)[0], (*r)[1], (*r)[2]};
  }
  const bool both = p.Has("both");
  if (both && p.Has("left"))
    throw UsageError("--both holds the right and the left shoulder: drop --left");
  if (p.Has("left")) {
    sp.rightSide = false;
    sp.glenoidCentreMm[0] = -sp.glenoidCentreMm[0];
  }
  PhantomCTOptions ct = ScapulaCTDefaults();
  ct.noiseHU = p.GetDouble("noise", 0, 1000).value_or(ct.noiseHU);
  ct.inPlaneSpacingMm = p.GetDouble("pixel-mm", 0.3, 3).value_or(ct.inPlaneSpacingMm);
  ct.sliceSpacingMm = p.GetDouble("slice-mm", 0.5, 5).value_or(ct.sliceSpacingMm);
  std::optional<std::vector<double>> window = p.GetDoubles("window", 2);
  std::optional<StoredAxes> axes;
  if (const auto text = p.Get("axes")) {
    if (!window)
      throw UsageError("--axes applies to the 8-bit --window volume (the DICOM series is axial)");
    try {
      axes = ParseStoredAxes(*text);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--axes: ") + e.what());
    }
  }
  if (window && !((*window)[1] > 0))
    throw UsageError("--window: the width must be > 0 HU");
  DicomWriteOptions dicom;
  if (const auto syntax = p.Get("compress")) {
    if (window)
      throw UsageError("--compress applies to the DICOM series, not the 8-bit --window volume");
    dicom.transferSyntax = *syntax;
    if (*syntax != "rle" && *syntax != "jpeg-lossless" && *syntax != "jpeg-ls" &&
        *syntax != "jpeg2000")
      throw UsageError("--compress must be rle, jpeg-lossless, jpeg-ls or jpeg2000");
  }
  const std::string out = p.Get("out", "");
  RequireEmptyOut(out);
  const ScapulaPhantom ph(sp);
  // Both shoulders: the left is the right's mirror image in x (the patient's midline at x = 0),
  // turned by the same rotation about its own glenoid centre.
  std::optional<ScapulaPhantom> left;
  if (both) {
    ScapulaPhantomParams leftParams = sp;
    leftParams.rightSide = false;
    leftParams.glenoidCentreMm[0] = -sp.glenoidCentreMm[0];
    left.emplace(leftParams);
  }
  const bool quiet = p.Has("quiet");
  std::string wrote = out;
  if (window || both) {
    // The CT (an 8-bit volume, or a DICOM series of both shoulders) and the truth, each written
    // atomically; a failure removes the folder when it was made here.
    const bool created = !fs::exists(out);
    try {
      std::vector<const ScapulaPhantom*> phantoms{&ph};
      if (left)
        phantoms.push_back(&*left);
      CTImage image = MakeScapulaCT(phantoms, ct, Progress(TerminalProgress(quiet)));
      if (axes)
        image = StoreAlongAxes(image, *axes);
      if (window) {
        fs::create_directories(out);
        wrote = (fs::path(out) / "ct.nrrd").string();
        SaveWindowedVolume(image, (*window)[0], (*window)[1], wrote);
      } else {
        dicom.seriesDescription = "BoneMachining scapula phantom, both shoulders";
        WriteDicomSeries(image, out, dicom);
      }
      WriteFileAtomic((fs::path(out) / "truth.json").string(), ScapulaTruthJson(ph).dump(2) + "\n");
      if (left)
        WriteFileAtomic((fs::path(out) / "truth_left.json").string(),
                        ScapulaTruthJson(*left).dump(2) + "\n");
    } catch (...) {
      std::error_code ec;
      if (created)
        fs::remove_all(out, ec);
      throw;
    }
  } else {
    WriteScapulaSeries(ph, out, ct, dicom, Progress(TerminalProgress(quiet)));
  }
  if (!quiet && isatty(2))
    std::fprintf(stderr, "\n");
  const std::array<double, 2> mapping =
      window ? WindowToHUMapping((*window)[0], (*window)[1]) : std::array<double, 2>{1, 0};
  const ScapulaTruth& t = ph.Truth();
  const auto& c = t.glenoidCentre;
  const auto& n = t.faceNormal;
  std::cout << "phantom:     scapula ("
            << (both           ? "both shoulders"
                : sp.rightSide ? "right shoulder"
                               : "left shoulder")
            << ", "
            << (window ? "8-bit window " + Fx((*window)[0], 0) + " / " + Fx((*window)[1], 0) +
                             " HU: read it with --hu-mapping " + Fx(mapping[0], 6) + "," +
                             Fx(mapping[1], 1)
                       : std::string("DICOM series, CT"))
            << ", " << Fx(ct.inPlaneSpacingMm, 2) << " mm pixels, " << Fx(ct.sliceSpacingMm, 2)
            << " mm slices)" << (sp.wearDepthMm > 0 ? ", B2 posterior wear" : "")
            << "\nwrote:       " << wrote << " and " << (fs::path(out) / "truth.json").string()
            << (both ? " (the right shoulder's; the left's in truth_left.json)" : "")
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
  p.Words("CT|phantom", "DICOM folder, volume file (.nrrd/.nhdr/.mha/.mhd/.nii/.nii.gz, .vti/.vtk "
                        "read by VTK and kept as DIR/ct.mha for the steps) or .inv3 project "
                        "holding the shoulder, a series on a PACS "
                        "(pacs://[AET@]HOST:PORT/SERIES-UID[?aet=OURS], fetched into DIR/ct "
                        "first, bmsim pacs find lists them), or 'phantom': the scapula phantom "
                        "(its DICOM series is written to DIR/ct first)")
      .Value("o,out", "DIR",
             "folder to create (must not exist or be empty; required); receives plan.json (both "
             "steps), step1-guide-pin.json, step2-ream.json (single-step scenes for bmsim run), "
             "plan_report.md/.html/.json; with no glenoid found, the report and "
             "plan_failure.png (the bone searched, the rejected joints marked)")
      .Value("landmarks", "FILE",
             "landmarks replacing detected ones: a plan.json (its edited planning.landmarks) or "
             "a JSON object of glenoid_centre_mm, face_normal, trigonum_mm, inferior_angle_mm "
             "(world mm, LPS), rim_points_mm (three or more points on the rim, in place of "
             "the centre and normal) or face_point_mm (a point on the glenoid face: the glenoid "
             "is traced around it); a centre and normal alone make a plan")
      .Value("side", "left|right|auto",
             "the shoulder to plan (default auto: the one found; with both in the scan, name "
             "one)")
      .Real("target-version", -44.9, 44.9, "DEG", "target version of the reaming axis (default 0)")
      .Real("target-inclination", -44.9, 44.9, "DEG", "target inclination (default 0)")
      .Real("reamer-diameter", 10, 60, "MM",
            "reamer size checked against the glenoid (default 36.5)")
      .Real("ream-depth", 0.01, 10, "MM", "reaming depth below the glenoid centre (default 2)")
      .Real("pin-radius", 0.01, 5, "MM",
            "guide-pin hole radius (default 3.2; above the nipple's 3)")
      .Real("pin-depth", 0.01, 40, "MM", "guide-pin depth (default: ream depth + nipple 6 + 2 mm)")
      .Int("resolution", 32, 1024,
           "voxmap cells along the bone's longest side for detection (default 256)");
  AddCTOptions(p, CTOptionsFor::Plan);
  p.Real("phantom-version", -45, 45, "DEG", "phantom: its glenoid version (default -12)")
      .Real("phantom-inclination", -45, 45, "DEG", "phantom: its inclination (default 8)")
      .Flag("b2", "phantom: posterior wear (a biconcave Walch B2 face)")
      .Flag("q,quiet", "no progress bar")
      .Footer("Exit status 3: no glenoid found (or a placed one that cannot be used), or the "
              "reamer would start inside bone (a humeral head joined to the glenoid: give "
              "--exclude on it); the report says why. A measurement the scan does not allow "
              "(the trigonum or the inferior angle out of view) is reported as not available "
              "and the plan is made from the rest.");
}

static int PlanCommand(const ParsedArgs& p) {
  if (p.Positional().size() != 1)
    throw UsageError("name one CT (or phantom)");
  const std::string input = p.Positional()[0];
  const bool phantom = input == "phantom";
  const bool fromPacs = input.rfind("pacs://", 0) == 0;
#ifdef BM_WITH_DCMTK
  const std::optional<bm::PacsSeriesUrl> pacs = fromPacs ? std::optional<bm::PacsSeriesUrl>([&] {
    try {
      return bm::ParsePacsUrl(input);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }())
                                                         : std::nullopt;
#else
  if (fromPacs)
    throw UsageError("this bmsim was built without DCMTK: it cannot fetch from a PACS");
#endif
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
  ImportOptions io = CTOptionsFromArgs(p, CTOptionsFor::Plan);
  io.resolution = int(p.GetInt("resolution", 32, 1024).value_or(256));
  const std::string sideText = p.Get("side").value_or("auto");
  if (sideText != "left" && sideText != "right" && sideText != "auto")
    throw UsageError("--side must be left, right or auto");
  const ShoulderSide side = sideText == "left"    ? ShoulderSide::Left
                            : sideText == "right" ? ShoulderSide::Right
                                                  : ShoulderSide::Any;
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
  if (phantom)
    for (const char* o : {"series", "raw-threshold", "hu-mapping", "allow-outside-data"})
      if (p.Has(o))
        throw UsageError(std::string("--") + o +
                         " applies to a CT read from a file, not the phantom");
  if (!phantom && !fromPacs && !fs::exists(input))
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
  fs::path finalCT = fs::path(out) / "ct";
  const auto placeCT = [&] {
    if (!stagedCT.empty())
      fs::rename(stagedCT, finalCT);
    stagedCT.clear();
  };
  bool vtkImage = false;
  if (phantom) {
    const ScapulaPhantom ph(sp);
    stagedCT = TemporarySibling(finalCT.string());
    cleanup.ct = stagedCT;
    ctPath = stagedCT;
    WriteScapulaSeries(ph, ctPath, ScapulaCTDefaults(), {}, progress.Range(0, 0.3));
    ctRef = fs::absolute(finalCT).string();
    truth = ScapulaTruthJson(ph);
    source = finalCT.string() + " (scapula phantom, version " + Fx(sp.versionDeg) +
             " deg, inclination " + Fx(sp.inclinationDeg) + " deg" +
             (sp.wearDepthMm > 0 ? ", B2" : "") + ")";
  } else if (fromPacs) {
#ifdef BM_WITH_DCMTK
    // The series fetched whole into DIR/ct (under a temporary's name until the plan is written):
    // the step scenes read it there.
    stagedCT = TemporarySibling(finalCT.string());
    cleanup.ct = stagedCT;
    progress(0.0, "fetching the series from the PACS");
    const int n = bm::GetSeries(pacs->server, "", pacs->seriesInstanceUid, stagedCT);
    ctPath = stagedCT;
    ctRef = fs::absolute(finalCT).string();
    source = finalCT.string() + " (series " + pacs->seriesInstanceUid + ", " + std::to_string(n) +
             " instances, from PACS " + pacs->server.calledAet + "@" + pacs->server.host + ":" +
             std::to_string(pacs->server.port) + ")";
#endif
  } else {
    ctPath = input;
    ctRef = fs::absolute(input).string();
    source = ctRef;
    // A VTK image is copied as DIR/ct.mha (under a temporary's name until the plan is written):
    // the step scenes' sessions read the copy.
    finalCT = fs::path(out) / "ct.mha";
    stagedCT = TemporarySibling(finalCT.string());
    cleanup.ct = stagedCT;
  }
  // Detection sees every bone: the exclude points are for the step scenes' bone.
  ImportOptions detectIo = io;
  detectIo.segmentation.excludeSeedsMm.clear();
  ImportResult r = ImportCT(ctPath, detectIo, stagedCT, vtkImage,
                            progress.Range(phantom || fromPacs ? 0.3 : 0, 0.9));
  if (phantom || fromPacs) {
    r.source = finalCT.string(); // where it is once the plan is written
  } else if (vtkImage) {
    ctRef = fs::absolute(finalCT).string();
  } else {
    stagedCT.clear(); // no copy was made
  }
  cleanup.armed = false;
  progress(0.95, "finding the glenoid");
  PlanReportInput rep;
  rep.source = source;
  rep.importSummary = r.Report();
  rep.truth = truth;
  const SegmentedBone bone(r.voxmap);
  DetectionOptions detect;
  detect.side = side;
  detect.scanSpacingMm = std::max({r.ctSpacing[0], r.ctSpacing[1], r.ctSpacing[2]});
  detect.scanBounds = r.ctBounds; // the field of view: the CT, within a region given
  if (io.roiMm)
    for (size_t a = 0; a < 3; ++a) {
      detect.scanBounds->lo[a] = std::max(detect.scanBounds->lo[a], io.roiMm->lo[a]);
      detect.scanBounds->hi[a] = std::min(detect.scanBounds->hi[a], io.roiMm->hi[a]);
    }
  GlenoidLandmarks L;
  GlenoidMeasurements m;
  GlenoidPlan plan;
  const bool placed = ov.glenoidCentre || ov.facePoint || !ov.rimPoints.empty();
  auto detectOn = [&](const SegmentedBone& b) {
    return side == ShoulderSide::Any && !placed ? DetectOneShoulder(b, ov, detect)
                                                : DetectLandmarks(b, ov, detect);
  };
  // A humeral head joined to its glenoid at the threshold: cut off along its sphere, and the
  // detection run again (bmJoinedHeadCut.h).
  std::optional<SegmentedBone> cutBone;
  try {
    std::optional<HeadCut> cut;
    if (placed) {
      L = detectOn(bone);
    } else {
      HeadCutOptions hc;
      hc.scanSpacingMm = detect.scanSpacingMm;
      LandmarksOnCut found = DetectCuttingAJoinedHead(r.voxmap, bone, detectOn, hc);
      L = std::move(found.landmarks);
      cut = std::move(found.cut);
      cutBone = std::move(found.bone);
    }
    const SegmentedBone& used = cutBone ? *cutBone : bone;
    if (cut) {
      rep.importSummary += HeadCutSummary(*cut);
      io.segmentation.excludeHeads.push_back(cut->head);
    }
    m = MeasureGlenoid(L);
    plan = MakeGlenoidPlan(L, m, po);
    try {
      CheckToolStartsOutsideBone(used, L, plan);
    } catch (const PlanBlocked& e) {
      if (io.segmentation.excludeSeedsMm.empty())
        throw;
      plan.warnings.push_back(std::string(e.what()) +
                              " (exclude points are given: check that the step's bone leaves it "
                              "out)");
    }
    // The user's point for the steps' bone must be on the glenoid's scapula.
    if (const auto sd = p.GetDoubles("seed", 3)) {
      const int on = used.LabelAt({(*sd)[0], (*sd)[1], (*sd)[2]});
      if (on != L.scapulaLabel)
        throw UsageError("--seed (" + Fx((*sd)[0]) + ", " + Fx((*sd)[1]) + ", " + Fx((*sd)[2]) +
                         ") mm is " + (on ? "on another bone than" : "not on bone of") +
                         " the glenoid's scapula: the step scenes keep the bone there");
    }
  } catch (const std::runtime_error& e) {
    // No glenoid, or a plan whose tool would start inside bone: the report says why.
    if (!dynamic_cast<const NoGlenoidFound*>(&e) && !dynamic_cast<const PlanBlocked*>(&e)) {
      cleanup.armed = true; // nothing half written: the folder made here, or the CT staged
      throw;
    }
    rep.failure = e.what();
    placeCT();
#ifdef BM_WITH_REPORT
    // The bone searched, with the joints the failure names marked.
    if (const auto* none = dynamic_cast<const NoGlenoidFound*>(&e)) {
      try {
        WriteFailurePicture((fs::path(out) / "plan_failure.png").string(), r.voxmap,
                            none->rejectedAt);
        rep.failurePicture = "plan_failure.png";
      } catch (const std::exception& pictureError) {
        std::cerr << "bmsim plan: the failure's picture was not drawn: " << pictureError.what()
                  << "\n";
      }
    }
#endif
    WritePlanFiles(out, rep, nullptr);
    if (!quiet && isatty(2))
      std::fprintf(stderr, "\n");
    std::cerr << "bmsim plan: " << e.what() << "\nwrote " << (fs::path(out) / "plan_report.md")
              << " (no plan)\n";
    return 3;
  }
  rep.landmarks = &L;
  rep.measurements = &m;
  rep.plan = &plan;
  // The step scenes read the CT as the plan did: its intensity, threshold, series and exclude
  // points; the plan's region and seed (or the one given).
  nlohmann::json settings = ImportOptionsToJson(io);
  settings["ct"] = ctRef;
  PlanScenes scenes = MakePlanScenes(L, m, plan, settings);
  if (const auto s = p.GetDoubles("seed", 3)) // the user's point on the scapula
    for (nlohmann::json* j : {&scenes.plan, &scenes.pin, &scenes.ream})
      (*j)["bone"]["ct"]["seed"] = *s;
  placeCT();
  WritePlanFiles(out, rep, &scenes);
  progress(1.0, "planned");
  if (!quiet && isatty(2))
    std::fprintf(stderr, "\n");
  const auto& c = L.glenoidCentre;
  const auto& a = plan.axis;
  std::cout << "CT:            " << source << "\n"
            << "glenoid:       " << L.side << " shoulder, centre (" << Fx(c[0]) << ", " << Fx(c[1])
            << ", " << Fx(c[2]) << ") mm (" << L.centreSource << "), " << Na(m.heightMm, "mm")
            << " x " << Na(m.widthMm, "mm") << ", radius of curvature " << Na(m.faceRadiusMm, "mm")
            << "\n"
            << "version:       " << Na(m.friedmanVersionDeg, "deg") << " (Friedman 2D), "
            << Na(m.version3DDeg, "deg") << " (3D)\n"
            << "inclination:   " << Na(m.inclinationDeg, "deg") << " (3D)\n"
            << "axis:          (" << Fx(a[0], 4) << ", " << Fx(a[1], 4) << ", " << Fx(a[2], 4)
            << "): "
            << (plan.corrected ? "version " + Fx(plan.axisVersionDeg) + " deg, inclination " +
                                     Fx(plan.axisInclinationDeg) + " deg, correction " +
                                     Fx(plan.correctionDeg) + " deg"
                               : std::string("the face normal, not corrected"))
            << "\n"
            << "reamer:        " << Fx(po.reamerDiameterMm) << " mm, "
            << (plan.reamerFits            ? "within the glenoid"
                : std::isfinite(m.widthMm) ? "overhangs the glenoid"
                                           : "size not checked (no rim)")
            << "\n";
  for (const auto& [key, why] : m.notAvailable)
    std::cout << "not available: " << key << ": " << why << "\n";
  for (const auto& w : plan.warnings)
    std::cout << "warning:       " << w << "\n";
  std::cout << "wrote:         " << out << "/plan.json, step1-guide-pin.json, step2-ream.json, "
            << "plan_report.md/.html/.json" << (vtkImage ? ", ct.mha (the CT for the steps)" : "")
            << "\n";
  return 0;
}

BM_REGISTER_COMMAND(plan, "plan glenoid reaming on a shoulder CT (or the scapula phantom)",
                    PlanCommandOptions, PlanCommand);

} // namespace bm::cli
#endif
