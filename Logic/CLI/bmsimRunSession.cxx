#include "bmsimRunSession.h"
#include "bmsimStagedOutput.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "bmAtomicFile.h"
#include "bmBreakthrough.h"
#include "bmsimCommand.h"
#include "bmsimProgressBar.h"
#include "bmEdgeQuadrature.h"
#include "bmHapticSession.h"
#include "bmMachiningSetup.h"
#include "bmSceneBone.h"
#include "bmScriptedDevice.h"
#include "bmSessionBuilder.h"
#include "bmSessionRecorder.h"
#include "bmTouchDevice.h"
#include "bmTouchProbe.h"

namespace bm::cli {

/// How long the Touch's probe may take, s (opening a Touch takes about a second).
constexpr double kTouchProbeTimeoutS = 10.0;

void SessionRunOptions(ParsedArgs& p) {
  const std::string maxForce = [] {
    std::ostringstream os;
    os << DeviceLimits().maxForceN;
    return os.str();
  }();
  p.Choice("device", {"scripted", "touch"},
           "run through a haptic session with this device: scripted (a simulated hand or feed on "
           "a Touch) or touch (OpenHaptics libHD.so, $BM_LIBHD overrides)")
      .Choice("mode", {"feed", "force", "trajectory", "hand"},
              "scripted device: prescribed feed and speed (default), a constant push, a "
              "trajectory file, or a hand's rising push with tremor")
      .Real("force", 0.0, DeviceLimits().maxForceN, "N",
            "force and hand modes: the push along the feed at the device, N, at most the "
            "Touch's " +
                maxForce + " N (default 2.5)")
      .Real("force-scale", 1e-3, kMaxForceScale, "S",
            "tool force = S x device force (default: the tool's, a 2.5 N push at a surgeon's feed)")
      .Int("seed", 0, 1000000000, "hand mode: tremor seed (default 1)")
      .Flag("trained-hand", "force and hand modes: the hand stops pushing at breakthrough, after "
                            "a 0.1 s reaction (default: it pushes on)")
      .Value("trajectory", "FILE", "trajectory mode: time_s,x_mm,y_mm,z_mm[,qw,qx,qy,qz] rows")
      .Real("duration", 0.001, 3600, "S",
            "seconds of session time (default: feed mode the trial's depth, force and hand "
            "modes 2 s, trajectory its length, touch 10 s)")
      .Value("record", "FILE", "also write the record to FILE (.h5 needs HDF5, else .csv)")
      .Choice("contact", {"cutting", "kim"}, "contact model (default cutting)")
      .Choice("rendering", {"coupled", "direct"}, "force rendering (default coupled)")
      .Real("rate", 10, 10000, "HZ", "haptic rate, Hz (default 1000)")
      .Int("overrun-limit", -1, 1000000,
           "pause after more than N overruns in 100 frames, -1 never (default: touch 5, "
           "scripted never)");
}

Voxmap SceneBone(const bm::Scene& scene) {
  if (scene.bone.type == "block" || !CanImportSceneBones())
    return MakeSceneBone(scene);
  ProgressBar bar("import bone");
  return MakeSceneBone(scene, [&](double f, const std::string&) { return bar.Update(f); });
}

void CheckWritableOutput(const std::string& what, const std::string& path, bool isFolder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path p = fs::absolute(path, ec);
  if (ec || path.empty())
    throw UsageError(what + " '" + path + "': not a usable path");
  if (!isFolder && fs::is_directory(p, ec))
    throw UsageError(what + " '" + path + "' is a folder, expected a file");
  if (isFolder && fs::exists(p, ec) && !fs::is_directory(p, ec))
    throw UsageError(what + " '" + path + "' is a file, expected a folder");
  // A folder is created with its parents: the nearest existing folder above it must be writable.
  // A file is written into its folder, which must exist.
  fs::path dir = isFolder ? p : p.parent_path();
  if (!isFolder && !fs::is_directory(dir, ec))
    throw UsageError(what + " '" + path + "': the folder '" + dir.string() + "' does not exist");
  while (!dir.empty() && !fs::exists(dir, ec) && dir != dir.parent_path())
    dir = dir.parent_path();
  if (!fs::is_directory(dir, ec))
    throw UsageError(what + " '" + path + "': '" + dir.string() + "' is not a folder");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw UsageError(what + " '" + path + "': cannot write in '" + dir.string() + "'");
  if (!isFolder && fs::exists(p, ec) && ::access(p.c_str(), W_OK) != 0)
    throw UsageError(what + " '" + path + "': the file is not writable");
}

InputFiles RunInputs(const bm::Scene& scene, const ParsedArgs& args) {
  InputFiles inputs;
  std::error_code ec;
  if (!args.Positional().empty() && std::filesystem::is_regular_file(args.Positional()[0], ec))
    inputs.AddFile(args.Positional()[0], "the scene file");
  AddSceneBoneInputs(scene, inputs);
  if (const auto trajectory = args.Get("trajectory"))
    inputs.AddFile(*trajectory, "the --trajectory file");
  return inputs;
}

void CheckRunOutputs(const bm::Scene& scene, const ParsedArgs& args, const std::string& outDir,
                     const std::vector<std::string>& written) {
  const InputFiles inputs = RunInputs(scene, args);
  InputFiles own;
  for (const std::string& name : written) {
    const std::string path = (std::filesystem::path(outDir) / name).string();
    inputs.CheckOutput(path, "the output");
    own.AddFile(path, "a file this run writes into --out,");
  }
  if (const auto record = args.Get("record")) {
    inputs.CheckOutput(*record, "--record");
    own.CheckOutput(*record, "--record");
  }
}

bool WantsSession(const ParsedArgs& args) {
  return args.Has("mode") || args.Has("device");
}

namespace {
struct Stats {
  double mean = 0, sd = 0, max = 0;
  size_t n = 0;
};
Stats Describe(const std::vector<double>& v) {
  Stats s;
  s.n = v.size();
  if (v.empty())
    return s;
  for (double x : v) {
    s.mean += x;
    s.max = std::max(s.max, x);
  }
  s.mean /= double(v.size());
  for (double x : v)
    s.sd += (x - s.mean) * (x - s.mean);
  s.sd = v.size() > 1 ? std::sqrt(s.sd / double(v.size() - 1)) : 0.0;
  return s;
}
nlohmann::json ToJson(const Stats& s) {
  return {{"mean", s.mean}, {"sd", s.sd}, {"max", s.max}, {"frames", s.n}};
}
} // namespace

int RunSessionScene(const bm::Scene& scene, const ParsedArgs& args, const std::string& outDir) {
  SessionRequest req;
  const std::string deviceName = args.Get("device", "scripted");
  if (deviceName != "scripted" && deviceName != "touch")
    throw UsageError("--device must be scripted or touch for a session run, not '" + deviceName +
                     "'");
  req.device = deviceName == "touch" ? SessionDevice::Touch : SessionDevice::Scripted;
  const std::string mode = args.Get("mode", "feed");
  if (mode != "feed" && mode != "force" && mode != "trajectory" && mode != "hand")
    throw UsageError("--mode must be feed, force, trajectory or hand, not '" + mode + "'");
  req.mode = mode == "feed"    ? ScriptMode::Feed
             : mode == "force" ? ScriptMode::Force
             : mode == "hand"  ? ScriptMode::Hand
                               : ScriptMode::Trajectory;
  req.forceScale = args.GetDouble("force-scale", 1e-3, kMaxForceScale).value_or(0.0);
  try {
    req.contact = ContactMethodFromString(args.Get("contact", "cutting"));
    req.rendering = RenderingFromString(args.Get("rendering", "coupled"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (auto v = args.GetInt("overrun-limit", -1, 1000000))
    req.overrunLimit = int(*v);
  if (auto r = args.GetDouble("rate", 10, 10000))
    req.rateHz = *r;
  req.realTime = true;
  req.clDevice = args.Get("cl-device", ""); // bmsim run's option (--backend opencl)
  // The push is the hand's at the device: at most the device's maximum force (the Touch's for a
  // scripted device, the nominal one for the Touch before it reports its own).
  const DeviceLimits nominal;
  req.appliedForceN = args.GetDouble("force", 0.0, nominal.maxForceN).value_or(kFirmPushN);
  if (auto seed = args.GetInt("seed", 0, 1000000000))
    req.handSeed = uint64_t(*seed);
  req.stopAtBreakthrough = args.Has("trained-hand");
  if (req.stopAtBreakthrough && mode != "force" && mode != "hand")
    throw UsageError("--trained-hand needs --mode force or hand (a hand that pushes)");
  // A hand on a Touch holds it for 10 s unless told otherwise; scripted runs last the device's
  // own time (bmSessionBuilder.h).
  req.durationS = args.GetDouble("duration", 0.001, 3600)
                      .value_or(req.device == SessionDevice::Touch ? 10.0 : 0.0);
  const auto record = args.Get("record");
  CheckWritableOutput("--out", outDir, true);
  if (record)
    CheckWritableOutput("--record", *record, false);
  if (record &&
      (std::filesystem::path(*record).extension() == ".h5" ||
       std::filesystem::path(*record).extension() == ".hdf5") &&
      !HasHdf5())
    throw UsageError("--record " + *record + ": this build has no HDF5; use a .csv file");
  // No output may replace an input (the scene, its CT, the trajectory) or another output.
  CheckRunOutputs(scene, args, outDir, {"session.csv", "summary.json"});
  if (req.mode == ScriptMode::Trajectory && req.device == SessionDevice::Scripted) {
    const auto file = args.Get("trajectory");
    if (!file)
      throw UsageError("--mode trajectory needs --trajectory FILE");
    req.trajectory = LoadTrajectoryCsv(*file);
  }
  try {
    ValidateSessionRequest(req);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }

  // A Touch's library is first tried in a child process, every step a session takes (force
  // output and the servo loop at zero force): a driver that crashes or hangs ends the child, and
  // bmsim refuses the device by name instead of dying with it (bmTouchProbe.h).
  if (req.device == SessionDevice::Touch) {
    const TouchProbeResult probe = ProbeTouch(kTouchProbeTimeoutS);
    if (!probe.ready)
      throw std::runtime_error(probe.message + " (tried in a child process; no session started)");
  }
  // Unless resolutions or threads were given, the session models no more than it needs
  // (bmSessionGrid.h): no finer than the CT's spacing and this machine's measured limit.
  req.chooseGrid =
      !args.Has("voxmap-resolution") && !args.Has("shell-resolution") && !args.Has("threads");
  BuiltSession built = [&] {
    if (scene.bone.type == "block" || !CanImportSceneBones())
      return BuildSession(scene, req);
    ProgressBar bar("import bone");
    return BuildSession(scene, req, [&](double f, const std::string&) { return bar.Update(f); });
  }();
  MachiningSetup& setup = *built.setup;
  const Scene& used = setup.GetScene(); // the scene at the resolutions the session runs
  const std::shared_ptr<Device>& device = built.device;
  const SessionOptions& so = built.options;
  const double duration = built.durationS;
  // Every frame is recorded (session.csv, --record): a session longer than a recording may hold
  // would be written and then refused by bmsim replay.
  if (std::isfinite(duration) && duration * so.rateHz > double(kMaxRecordingFrames)) {
    std::ostringstream os;
    os << "--duration " << duration << " s at --rate " << so.rateHz << " Hz makes "
       << int64_t(std::ceil(duration * so.rateHz)) << " frames; a recording holds at most "
       << kMaxRecordingFrames << " (one hour at 1 kHz): shorten the session or lower the rate";
    throw UsageError(os.str());
  }
  HapticSession session(setup, device, so);
  std::vector<FrameRecord> frames;
  if (so.maxFrames > 0) // < 0: no frame limit (the device ends the session)
    frames.reserve(size_t(std::min<int64_t>(so.maxFrames, 3600000)));
  session.Start();
  std::cout << "session " << scene.name << ": " << deviceName << " device, " << mode << " mode, "
            << ToString(so.proxy.method) << "/" << ToString(so.proxy.rendering) << ", " << so.rateHz
            << " Hz, " << duration << " s, force scale " << so.proxy.coupling.forceScale
            << " (tool N per device N)\n";
  if (!built.gridReason.empty())
    std::cout << "  resolutions chosen for the session: " << built.gridReason << "\n";
  if (!built.startNote.empty())
    std::cout << "  warning: " << built.startNote << "\n";
  while (!session.WaitUntilPaused(0.05))
    session.DrainRecords(frames);
  const SessionSnapshot last = session.Snapshot();
  session.Stop();
  session.DrainRecords(frames);
  const TimingStats ts = session.Timing();

  std::vector<double> thrust, torque, feed, force;
  for (const auto& f : frames) {
    force.push_back(Eigen::Vector3d(f.deviceForce[0], f.deviceForce[1], f.deviceForce[2]).norm());
    if (f.feedMmPerRev > 0) {
      thrust.push_back(f.thrustN);
      torque.push_back(f.torqueNmm);
      feed.push_back(f.feedMmPerRev);
    }
  }
  // Depth of the foremost cutting point below the entry.
  const double depth =
      frames.empty()
          ? 0.0
          : ToolDepthMm(setup,
                        Eigen::Vector3d(frames.back().proxyPos[0], frames.back().proxyPos[1],
                                        frames.back().proxyPos[2]),
                        setup.ToolRotation());
  // The breakthrough plunge, where the tool went through (a drill past the far cortex).
  const Breakthrough through = MeasureBreakthrough(frames, [&](const FrameRecord& f) {
    return ToolDepthMm(setup, Eigen::Vector3d(f.proxyPos[0], f.proxyPos[1], f.proxyPos[2]),
                       ToolRotationFromQuaternion(f.deviceQuat));
  });
  nlohmann::json breakthrough = nullptr;
  if (through.found)
    breakthrough = {{"time_s", through.timeS},
                    {"depth_mm", through.depthMm},
                    {"plunge_mm", through.plungeMm},
                    {"stopped", through.stopped},
                    {"stop_after_s", through.stopS}};
  nlohmann::json s = {
      {"scene", scene.name},
      {"trained_hand", req.stopAtBreakthrough},
      {"device", deviceName},
      {"mode", mode},
      {"applied_force_N", mode == "force" || mode == "hand" ? req.appliedForceN : 0.0},
      {"force_scale", so.proxy.coupling.forceScale},
      {"tool_max_force_N", session.Coupling().MaxForce()},
      {"contact", ToString(so.proxy.method)},
      {"rendering", ToString(so.proxy.rendering)},
      {"engine", setup.GetEngine().Name()},
      {"coefficients", setup.Model().ProvenanceJson()},
      {"rate_hz", so.rateHz},
      {"frames", frames.size()},
      {"duration_s", double(frames.size()) / so.rateHz},
      {"frame_ms_p50", ts.p50Ms},
      {"frame_ms_p99", ts.p99Ms},
      {"frame_ms_max", ts.maxMs},
      {"frame_ms_mean", ts.meanMs},
      {"overruns", ts.overruns},
      {"pause_reason", ToString(last.pauseReason)},
      {"thrust_N", ToJson(Describe(thrust))},
      {"torque_Nmm", ToJson(Describe(torque))},
      {"feed_mm_per_rev", ToJson(Describe(feed))},
      {"device_force_N", ToJson(Describe(force))},
      {"device_max_force_N", device->Limits().maxForceN},
      {"coupling_stiffness_N_per_mm", session.Coupling().Stiffness()},
      {"coupling_damping_Ns_per_mm", session.Coupling().Damping()},
      {"removed_volume_mm3", last.removedVolumeMm3},
      {"removed_voxels", last.removedVoxels},
      {"final_depth_mm", depth},
      {"breakthrough", breakthrough},
      {"dropped_records", last.droppedRecords},
      {"voxmap_resolution", used.voxmapResolution},
      {"shell_resolution", used.shellResolution},
      {"threads", used.threads},
      {"resolutions_chosen",
       built.gridReason.empty() ? nlohmann::json(nullptr) : nlohmann::json(built.gridReason)},
      {"start_lift_mm", built.startLiftMm}};
  Recording rec;
  rec.meta = {{"scene", used.ToJson()},
              {"scene_base_dir", scene.baseDir},
              {"session", SessionOptionsToJson(so, device->Limits())}};
  rec.frames = std::move(frames);
  StagedOutput staged(outDir); // the outputs appear together (bmsimStagedOutput.h)
  WriteRecordingCsv((std::filesystem::path(staged.Path()) / "session.csv").string(), rec);
  if (record)
    WriteRecording(*record, rec);
  WriteFileAtomic((std::filesystem::path(staged.Path()) / "summary.json").string(),
                  s.dump(2) + "\n");
  staged.Commit();
  std::cout << "  frames " << rec.frames.size() << ", frame p50 " << ts.p50Ms << " ms, p99 "
            << ts.p99Ms << " ms, max " << ts.maxMs << " ms, overruns " << ts.overruns << "\n"
            << "  thrust " << s["thrust_N"]["mean"].get<double>() << " N, torque "
            << s["torque_Nmm"]["mean"].get<double>() << " N mm, feed "
            << s["feed_mm_per_rev"]["mean"].get<double>() << " mm/rev, depth " << depth << " mm\n"
            << "  pause reason: " << ToString(last.pauseReason) << "\n";
  if (through.found) {
    std::cout << "  breakthrough at " << through.timeS << " s, " << through.depthMm
              << " mm deep: plunge " << (through.stopped ? "" : "at least ") << through.plungeMm
              << " mm"
              << (through.stopped ? ", the hand stopped it after " : ", still moving after ")
              << through.stopS << " s\n";
  }
  std::cout << "wrote " << outDir << "/session.csv and " << outDir << "/summary.json"
            << (record ? " and " + *record : std::string()) << "\n";
  return last.pauseReason == PauseReason::Finished ? 0 : 1;
}

} // namespace bm::cli
