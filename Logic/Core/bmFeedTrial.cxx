#include "bmFeedTrial.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <Eigen/Geometry>

#include "bmAtomicFile.h"
#include "bmEdgeQuadrature.h"
#include "bmGuideContact.h"

namespace bm {

double Percentile(std::vector<double> v, double pct) {
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  size_t rank = size_t(std::ceil(pct / 100.0 * v.size()));
  return v[std::clamp<size_t>(rank, 1, v.size()) - 1];
}

FeedPath::FeedPath(const MachiningSetup& setup)
    : T_(setup.GetScene().trial), Rot_(setup.ToolRotation()), Axis_(T_.axis.normalized()),
      Zf_(ForemostCuttingZ(setup.Tool())), Step_(T_.feedMmPerRev * T_.speedRpm / 60.0 * T_.frameS) {
}

FrameInput FeedPath::Frame(double depthMm, int64_t k) const {
  FrameInput in;
  in.rotation = Rot_;
  in.position = T_.entry - Axis_ * depthMm - Rot_ * Eigen::Vector3d(0, 0, Zf_);
  in.motion = -Axis_ * Step_;
  in.feedMmPerRev = T_.feedMmPerRev;
  in.speedRpm = T_.speedRpm;
  in.spindleAngle = 2.0 * 3.14159265358979323846 * T_.speedRpm / 60.0 * T_.frameS * double(k + 1);
  return in;
}

FeedTrial::FeedTrial(MachiningSetup& setup) : Setup_(setup) {
  const Scene& s = setup.GetScene();
  const double full = FullEngagementDepth(setup.Tool());
  EngagedDepth_ = full + 2 * setup.Bone().Spacing() + setup.Shell().Spacing();
  FinalDepth_ = s.trial.depthMm >= 0 ? s.trial.depthMm : full + s.trial.extraDepthMm;
}

bool FeedTrial::Run(const std::function<bool(double)>& progress) {
  const Scene& s = Setup_.GetScene();
  const TrialSpec& t = s.trial;
  const FeedPath path(Setup_);
  const double step = path.StepMm();
  const int64_t frames = int64_t(std::ceil((FinalDepth_ + t.clearanceMm) / step));
  Engine& engine = Setup_.GetEngine();
  const GuideContact guide(Setup_.Tool(), Setup_.Bone());
  Frames_.clear();
  Warnings_.clear();
  GuideBlocked_ = false;
  GuideStop_ = 0;
  SweptVolume_ = RemovedVolume_ = 0;
  RemovedVoxels_ = 0;
  Frames_.reserve(size_t(frames));
  CheckPath();
  for (int64_t k = 0; k < frames; ++k) {
    const double depth = -t.clearanceMm + step * double(k + 1);
    const FrameInput in = path.Frame(depth, k);
    if (guide.HasGuide() && guide.Blocked(in)) {
      GuideBlocked_ = true;
      GuideStop_ = depth - step;
      std::ostringstream w;
      w << std::fixed << std::setprecision(2) << "the " << Setup_.Tool().Kind()
        << "'s guide nipple (radius " << guide.RadiusMm() << " mm, " << guide.LengthMm()
        << " mm long) met solid bone at depth " << GuideStop_ << " mm of the planned "
        << FinalDepth_
        << " mm: the feed stopped there, as a rigid guide would. Drill the guide-pin hole "
           "(wider than the nipple, deeper than depth + nipple length) along the same axis first.";
      Warnings_.push_back(w.str());
      break;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const FrameResult r = engine.Step(in);
    const auto t1 = std::chrono::steady_clock::now();
    TrialFrame f;
    f.timeS = t.frameS * double(k + 1);
    f.depthMm = depth;
    f.feedMmPerRev = t.feedMmPerRev;
    f.thrustN = r.thrustN;
    f.torqueNmm = r.torqueNmm;
    f.frameMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
    f.removedVoxels = r.removedVoxels;
    f.removedVolumeMm3 = r.removedVolumeMm3;
    f.lateralN = std::hypot(r.forceTool(0), r.forceTool(1));
    Frames_.push_back(f);
    SweptVolume_ += r.sweptVolumeMm3;
    RemovedVolume_ += r.removedVolumeMm3;
    RemovedVoxels_ += r.removedVoxels;
    if (progress && (k % 256 == 0 || k + 1 == frames) && !progress(double(k + 1) / double(frames)))
      return false;
  }
  engine.SyncBone();
  if (!(RemovedVolume_ > 0))
    Warnings_.push_back("the run removed no bone: the tool never reached bone along the trial "
                        "(check the entry point, the axis and the depth)");
  return true;
}

void FeedTrial::CheckPath() {
  // Rays parallel to the axis, half a voxel apart along it, from the foremost cutting point's start
  // to its final depth: the axis itself and eight at half the tool's radius (a guided reamer's axis
  // runs down its pilot hole).
  const TrialSpec& t = Setup_.GetScene().trial;
  const Voxmap& bone = Setup_.Bone();
  const Eigen::Vector3d axis = t.axis.normalized();
  const Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  auto boneAt = [&](const Eigen::Vector3d& offset, double depth) {
    const Eigen::Vector3d p = t.entry + offset - axis * depth;
    std::array<int, 3> ijk{};
    return bone.VoxelAt({p(0), p(1), p(2)}, ijk) &&
           bone.Fraction(bone.Index(ijk[0], ijk[1], ijk[2])) >= 0.5;
  };
  std::ostringstream w;
  w << std::fixed << std::setprecision(2);
  if (boneAt(Eigen::Vector3d::Zero(), -t.clearanceMm)) {
    w << "the tool starts inside bone: its foremost cutting point, " << t.clearanceMm
      << " mm above the entry, is in bone, so the first frame cuts a whole layer at once (raise "
         "clearance_mm or move the entry to the bone's surface)";
    Warnings_.push_back(w.str());
    return;
  }
  std::vector<Eigen::Vector3d> rays{Eigen::Vector3d::Zero()};
  const double r = 0.5 * Setup_.Tool().OuterRadius();
  for (int k = 0; k < 8; ++k) {
    const double a = 2 * 3.14159265358979323846 * k / 8;
    rays.push_back(r * (std::cos(a) * e1 + std::sin(a) * e2));
  }
  const double step = 0.5 * bone.Spacing();
  for (const Eigen::Vector3d& ray : rays)
    for (double d = -t.clearanceMm; d <= FinalDepth_; d += step)
      if (boneAt(ray, d))
        return;
  w << "the entry lies outside all bone: from " << t.clearanceMm << " mm above the entry to "
    << FinalDepth_
    << " mm below it, the tool's axis and the rays at half its radius meet no voxel that is at "
       "least half bone";
  Warnings_.push_back(w.str());
}

nlohmann::json FeedTrial::Summary() const {
  const Scene& s = Setup_.GetScene();
  std::vector<double> thrust, torque, lateral, ms;
  // Statistics over full engagement; a trial that never engages every edge element (reaming to a
  // shallow depth) takes its last fifth of travel instead, and says so.
  const double reached = GuideBlocked_ ? GuideStop_ : FinalDepth_;
  const bool full = reached >= EngagedDepth_;
  const double from = full ? EngagedDepth_ : reached - 0.2 * (reached + s.trial.clearanceMm);
  for (const auto& f : Frames_) {
    ms.push_back(f.frameMs);
    if (f.depthMm >= from) {
      thrust.push_back(f.thrustN);
      torque.push_back(f.torqueNmm);
      lateral.push_back(f.lateralN);
    }
  }
  auto mean = [](const std::vector<double>& v) {
    double m = 0;
    for (double x : v)
      m += x;
    return v.empty() ? 0.0 : m / double(v.size());
  };
  auto sd = [&](const std::vector<double>& v) {
    const double m = mean(v);
    double q = 0;
    for (double x : v)
      q += (x - m) * (x - m);
    return v.size() < 2 ? 0.0 : std::sqrt(q / double(v.size() - 1));
  };
  const EdgeIntegral ref =
      IntegrateEdges(Setup_.Tool(), Setup_.Model(), s.trial.feedMmPerRev, s.trial.speedRpm);
  const double mT = mean(thrust), mM = mean(torque);
  // Errors compare like with like (Docs/Calibration.md section 8): the fully engaged mean with
  // the fully engaged reference; a partly engaged mean on the block (flat top at the entry, so the
  // engagement depth is the frame's depth) with the reference integrated at each of its frames'
  // depths. On any other bone the partial engagement has no reference: no error is given.
  std::string errorBasis = "full_engagement";
  EdgeIntegral same = ref;
  if (!full) {
    errorBasis = "none";
    if (s.bone.type == "block" && !thrust.empty()) {
      errorBasis = "partial_engagement_same_depths";
      same = {};
      int k = 0;
      for (const auto& f : Frames_)
        if (f.depthMm >= from) {
          const EdgeIntegral e =
              IntegrateEdges(Setup_.Tool(), Setup_.Model(), s.trial.feedMmPerRev, s.trial.speedRpm,
                             std::max(f.depthMm, 0.0), EdgeKind::None, 200);
          same.thrustN += e.thrustN;
          same.torqueNmm += e.torqueNmm;
          ++k;
        }
      same.thrustN /= k;
      same.torqueNmm /= k;
    }
  }
  auto error = [&](double measured, double reference) -> nlohmann::json {
    if (errorBasis == "none" || reference == 0)
      return nullptr;
    return (measured - reference) / reference;
  };
  const double analytic =
      s.bone.type == "block" ? VolumeBelowDepth(Setup_.Tool(), FinalDepth_) : -1.0;
  nlohmann::json j = {
      {"scene", s.name},
      {"method", ToString(s.method)},
      {"backend", s.backend},
      {"engine", Setup_.GetEngine().Name()},
      {"threads", s.threads},
      {"lips", s.lips == LipMode::TimeAveraged ? "averaged" : "instantaneous"},
      {"feed_mm_per_rev", s.trial.feedMmPerRev},
      {"speed_rpm", s.trial.speedRpm},
      {"voxmap_resolution", s.voxmapResolution},
      {"shell_resolution", s.shellResolution},
      {"voxel_mm", Setup_.Bone().Spacing()},
      {"shell_spacing_mm", Setup_.Shell().Spacing()},
      {"shell_elements", Setup_.Shell().Size()},
      {"shell_cutting_elements", Setup_.Shell().NumCutting()},
      {"frames", Frames_.size()},
      {"engaged_frames", thrust.size()},
      {"statistics_phase", full ? "full_engagement" : "last_fifth_of_travel"},
      {"engaged_depth_mm", EngagedDepth_},
      {"final_depth_mm", FinalDepth_},
      {"thrust_N", mT},
      {"torque_Nmm", mM},
      {"thrust_ripple", mT != 0 ? sd(thrust) / std::abs(mT) : 0.0},
      {"torque_ripple", mM != 0 ? sd(torque) / std::abs(mM) : 0.0},
      {"lateral_N", mean(lateral)},
      {"reference_thrust_N", ref.thrustN},
      {"reference_torque_Nmm", ref.torqueNmm},
      {"error_reference", errorBasis},
      {"error_reference_thrust_N",
       errorBasis == "none" ? nlohmann::json(nullptr) : nlohmann::json(same.thrustN)},
      {"error_reference_torque_Nmm",
       errorBasis == "none" ? nlohmann::json(nullptr) : nlohmann::json(same.torqueNmm)},
      {"thrust_error", error(mT, same.thrustN)},
      {"torque_error", error(mM, same.torqueNmm)},
      {"thrust_fraction_of_full_engagement", ref.thrustN != 0 ? mT / ref.thrustN : 0.0},
      {"coefficients", Setup_.Model().ProvenanceJson()},
      {"frame_ms_p50", Percentile(ms, 50)},
      {"frame_ms_p99", Percentile(ms, 99)},
      {"frame_ms_max", ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end())},
      {"removed_volume_mm3", RemovedVolume_},
      {"swept_volume_mm3", SweptVolume_},
      {"removed_voxels", RemovedVoxels_},
      {"reached_depth_mm", GuideBlocked_ ? GuideStop_
                           : Frames_.empty() ? -s.trial.clearanceMm
                                             : Frames_.back().depthMm},
      {"guide_blocked", GuideBlocked_},
      {"warnings", Warnings_},
  };
  if (analytic >= 0) {
    j["analytic_removed_volume_mm3"] = analytic;
    j["removed_volume_error"] = analytic > 0 ? (RemovedVolume_ - analytic) / analytic : 0.0;
  }
  return j;
}

void FeedTrial::WriteOutputs(const std::string& dir) const {
  std::ostringstream csv;
  csv << "time_s,depth_mm,feed_mm_per_rev,thrust_N,torque_Nmm,frame_ms,removed_voxels\n";
  csv << std::setprecision(9);
  for (const auto& f : Frames_)
    csv << f.timeS << ',' << f.depthMm << ',' << f.feedMmPerRev << ',' << f.thrustN << ','
        << f.torqueNmm << ',' << f.frameMs << ',' << f.removedVoxels << '\n';
  const std::string summary = Summary().dump(2) + "\n";
  std::filesystem::create_directories(dir);
  const std::filesystem::path d(dir);
  WriteFilesAtomic(
      {{(d / "forces.csv").string(), csv.str()}, {(d / "summary.json").string(), summary}});
}

} // namespace bm
