// bmsim replay - re-run a recorded session (bmSessionRecorder.h) and compare its forces.
#include <filesystem>
#include <iostream>
#include <sstream>

#include "bmAtomicFile.h"
#include "bmMachiningSetup.h"
#include "bmReplay.h"
#include "bmSessionRecorder.h"
#include "bmsimArgs.h"
#include "bmsimCommand.h"
#include "bmsimRunSession.h"

#include "bmInputFiles.h"

namespace {

void ReplayOptions(bm::cli::ParsedArgs& p) {
  p.Words("FILE", "a session recording (.h5 or .csv from bmsim run --record, or session.csv)")
      .Value("out", "DIR", "write DIR/replay.csv and DIR/replay_summary.json (default: none)")
      .Real("tolerance", 0.0, 1e6, "N",
            "largest accepted difference of each recorded quantity (N, N mm, mm, mm/rev, mm^3; "
            "default 1e-9)")
      .Footer("Exit status 0 when every quantity each frame produces matches the recording "
              "within the tolerance (coupling force, device force, thrust, torque, proxy "
              "position, feed, removed volume; removed voxels exactly), 1 otherwise, naming what "
              "differs; the outputs are written (together) only when they match. A recording "
              "with no frames, a non-finite value, frames not numbered 0, 1, 2, ... or times "
              "other than frame / rate is refused before anything runs. Recordings of any scene "
              "replay: a CT or phantom scene's bone is rebuilt from the recorded scene.");
}

int ReplayCommand(const bm::cli::ParsedArgs& p) {
  if (p.Positional().size() != 1)
    throw bm::cli::UsageError("needs exactly one FILE");
  const double tol = p.GetDouble("tolerance", 0.0, 1e6).value_or(1e-9);
  const auto out = p.Get("out");
  if (out) {
    bm::cli::CheckWritableOutput("--out", *out, true);
    // The replay's outputs may not replace the recording it reads.
    bm::InputFiles inputs;
    inputs.AddFile(p.Positional()[0], "the recording");
    for (const char* name : {"replay.csv", "replay_summary.json"})
      inputs.CheckOutput((std::filesystem::path(*out) / name).string(), "the output");
  }
  const bm::Recording rec = bm::ReadRecording(p.Positional()[0]);
  bm::CheckReplayable(rec);
  bm::Scene scene;
  try {
    scene = bm::RecordedScene(rec);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("recorded scene: ") + e.what());
  }
  bm::MachiningSetup setup(scene, bm::cli::SceneBone(scene));
  const bm::ReplayResult r = bm::Replay(rec, setup);
  const std::vector<std::string> differing = r.Differing(tol);
  const bool ok = differing.empty();
  nlohmann::json s = {{"file", p.Positional()[0]},
                      {"frames", r.frames},
                      {"max_coupling_force_diff_N", r.maxCouplingForceDiffN},
                      {"max_device_force_diff_N", r.maxDeviceForceDiffN},
                      {"max_thrust_diff_N", r.maxThrustDiffN},
                      {"max_torque_diff_Nmm", r.maxTorqueDiffNmm},
                      {"max_proxy_diff_mm", r.maxProxyDiffMm},
                      {"max_feed_diff_mm_per_rev", r.maxFeedDiffMmPerRev},
                      {"max_removed_volume_diff_mm3", r.maxRemovedVolumeDiffMm3},
                      {"max_removed_voxels_diff", r.maxRemovedVoxelsDiff},
                      {"tolerance_N", tol},
                      {"differing", differing},
                      {"reproduced", ok},
                      {"coefficients", setup.Model().ProvenanceJson()}};
  std::cout << "replayed " << r.frames << " frames of " << p.Positional()[0] << "\n"
            << "  max |coupling force difference| " << r.maxCouplingForceDiffN << " N, thrust "
            << r.maxThrustDiffN << " N, torque " << r.maxTorqueDiffNmm << " N mm, proxy "
            << r.maxProxyDiffMm << " mm\n"
            << "  device force " << r.maxDeviceForceDiffN << " N, feed " << r.maxFeedDiffMmPerRev
            << " mm/rev, removed volume " << r.maxRemovedVolumeDiffMm3 << " mm^3 and "
            << r.maxRemovedVoxelsDiff << " voxels per frame\n";
  if (ok) {
    std::cout << "  every recorded quantity reproduced\n";
  } else {
    std::string names;
    for (const std::string& d : differing)
      names += (names.empty() ? "" : ", ") + d;
    std::cout << "  NOT reproduced: " << names << " (beyond the tolerance " << tol << ")\n";
  }
  // A replay that fails leaves nothing; one that succeeds writes both files together.
  if (out && ok) {
    std::filesystem::create_directories(*out);
    bm::Recording again{rec.meta, r.replayed};
    const std::string csv = (std::filesystem::path(*out) / "replay.csv").string();
    std::ostringstream table;
    bm::WriteRecordingCsv(table, again);
    bm::WriteFilesAtomic(
        {{csv, table.str()},
         {(std::filesystem::path(*out) / "replay_summary.json").string(), s.dump(2) + "\n"}});
    std::cout << "wrote " << csv << " and replay_summary.json\n";
  } else if (out) {
    std::cout << "  nothing written to " << *out << " (the replay did not reproduce the forces)\n";
  }
  return ok ? 0 : 1;
}

} // namespace

BM_REGISTER_COMMAND(replay, "re-run a recorded session (FILE.h5|.csv) and compare its forces",
                    ReplayOptions, ReplayCommand);
