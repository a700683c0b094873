// vtkBMSessionSource.cxx - see vtkBMSessionSource.h.
#include "vtkBMSessionSource.h"

#include "bmBoneFractionImage.h"
#include "bmBoneSurface.h"
#ifdef BM_WITH_IO
#include "bmCTVoxmap.h"
#include "bmVoxmapFile.h"
#endif
#include "bmEdgeQuadrature.h"
#include "bmHapticSession.h"
#include "bmMachiningSetup.h"
#include "bmProgrammableDevice.h"
#include "bmScene.h"
#include "bmScriptedDevice.h"
#include "bmTouchDevice.h"
#include "vtkBMToolSource.h"

#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace {
/// Limits of the scripted robot and the mouse proxy: both are position sources with no hand on
/// them, held by a stiff arm (2000 N/mm, up to 5 kN), so the proxy lags the commanded pose by
/// thrust / K (0.25 mm at 500 N of reaming thrust). A Touch (3.3 N) could not push a 36.5 mm
/// reamer through cortical bone at a useful feed.
bm::DeviceLimits PositionSourceLimits() {
  bm::DeviceLimits l;
  l.maxForceN = 5000;
  l.maxStiffnessNPerMm = 2000;
  l.maxDampingNsPerMm = 2.0;
  l.workspaceRadiusMm = 1000;
  return l;
}

/// Most time one update spends re-extracting the bone's surface, ms (ParaView polls every 33 ms;
/// a quarter of that keeps the haptic frame as fast as without the view on two busy cores).
constexpr double kSurfaceBudgetMs = 8.0;
} // namespace

class vtkBMSessionSource::vtkInternals {
public:
  std::unique_ptr<bm::MachiningSetup> Setup;
  std::shared_ptr<bm::ProgrammableDevice> Mouse;
  std::unique_ptr<bm::HapticSession> Session;
  /// The cut bone's surface, in BoneSurface's default bricks of 8 voxels (one per voxmap
  /// generation brick: a cut re-extracts only the thin layer it changed).
  bm::BoneSurface Surface;
  vtkNew<vtkBMToolSource> Tool;
  int64_t LastFrame = -1;
  std::string Error;
  std::string TouchStatus;
  std::string PauseReason = "none";
  /// History rows (time_s, thrust_N, torque_Nmm, frame_ms, depth_mm), oldest first, and the
  /// session time of the next row to keep.
  std::deque<std::array<double, 5>> History;
  double NextHistoryS = 0;
  std::vector<bm::FrameRecord> Records; ///< drained from the session, reused
  vtkNew<vtkTable> HistoryTable;
  /// The cut bone's fill fractions for volume rendering, copied per changed brick.
  bm::BoneFractionImage Fraction;

  /// Depth (mm) of the foremost cutting point of a tool at (pos, rot) below the entry point.
  double Depth(const Eigen::Vector3d& pos, const Eigen::Matrix3d& rot) const {
    const bm::TrialSpec& t = this->Setup->GetScene().trial;
    const Eigen::Vector3d tip =
        pos + rot * Eigen::Vector3d(0, 0, bm::ForemostCuttingZ(this->Setup->Tool()));
    return (t.entry - tip).dot(t.axis.normalized());
  }

  /// Moves the session's new frame records into History (one row per stepS of session time)
  /// and drops rows older than keepS before the newest. GUI thread only (the ring's consumer).
  void DrainHistory(const Eigen::Matrix3d& rot, double stepS, double keepS) {
    this->Records.clear();
    this->Session->DrainRecords(this->Records);
    for (const bm::FrameRecord& r : this->Records) {
      if (r.timeS + 1e-9 < this->NextHistoryS)
        continue;
      const Eigen::Vector3d proxy(r.proxyPos[0], r.proxyPos[1], r.proxyPos[2]);
      this->History.push_back(
          {r.timeS, r.thrustN, r.torqueNmm, r.frameMs, this->Depth(proxy, rot)});
      this->NextHistoryS = r.timeS + stepS;
    }
    while (!this->History.empty() && this->History.front()[0] < this->History.back()[0] - keepS)
      this->History.pop_front();
    static const char* const names[5] = {"time_s", "thrust_N", "torque_Nmm", "frame_ms",
                                         "depth_mm"};
    vtkNew<vtkTable> table;
    for (int c = 0; c < 5; ++c) {
      vtkNew<vtkDoubleArray> column;
      column->SetName(names[c]);
      column->SetNumberOfTuples(vtkIdType(this->History.size()));
      for (size_t i = 0; i < this->History.size(); ++i)
        column->SetValue(vtkIdType(i), this->History[i][c]);
      table->AddColumn(column);
    }
    this->HistoryTable->ShallowCopy(table);
  }

  /// The mouse device's pose for a depth (mm) of the foremost cutting point below the entry.
  bm::DevicePose MousePose(double depthMm) const {
    const bm::TrialSpec& t = this->Setup->GetScene().trial;
    const Eigen::Matrix3d rot = this->Setup->ToolRotation();
    bm::DevicePose pose;
    pose.positionMm = t.entry - t.axis.normalized() * depthMm -
                      rot * Eigen::Vector3d(0, 0, bm::ForemostCuttingZ(this->Setup->Tool()));
    pose.rotation = rot;
    return pose;
  }
};

vtkStandardNewMacro(vtkBMSessionSource);

vtkBMSessionSource::vtkBMSessionSource() : Internals(new vtkInternals) {
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(4);
  this->SetScene("glenoid");
}

int vtkBMSessionSource::FillOutputPortInformation(int port, vtkInformation* info) {
  if (port == 2) {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
    return 1;
  }
  if (port == 3) {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkImageData");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

int vtkBMSessionSource::RequestInformation(vtkInformation*, vtkInformationVector**,
                                           vtkInformationVector* outputVector) {
  vtkInformation* info = outputVector->GetInformationObject(3);
  int extent[6] = {0, -1, 0, -1, 0, -1};
  double origin[3] = {0, 0, 0}, spacing[3] = {1, 1, 1};
  if (this->VolumeOutput && this->Internals->Setup) {
    const bm::Voxmap& v = this->Internals->Setup->Bone();
    for (int a = 0; a < 3; ++a) {
      extent[2 * a + 1] = v.Dims()[a] - 1;
      origin[a] = v.Origin()[a];
      spacing[a] = v.Spacing();
    }
  }
  info->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  info->Set(vtkDataObject::ORIGIN(), origin, 3);
  info->Set(vtkDataObject::SPACING(), spacing, 3);
  info->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 0);
  return 1;
}

vtkTable* vtkBMSessionSource::GetHistory() {
  return vtkTable::SafeDownCast(this->GetOutputDataObject(2));
}

vtkImageData* vtkBMSessionSource::GetBoneImage() {
  return vtkImageData::SafeDownCast(this->GetOutputDataObject(3));
}

std::string vtkBMSessionSource::ProbeTouch() {
  try {
    bm::TouchDevice touch;
    touch.Start();
    touch.Stop();
  } catch (const std::exception& e) {
    return e.what();
  }
  return std::string();
}

const char* vtkBMSessionSource::GetTouchStatus() {
  this->Internals->TouchStatus = ProbeTouch();
  return this->Internals->TouchStatus.c_str();
}

vtkBMSessionSource::~vtkBMSessionSource() {
  this->Stop();
  this->SetScene(nullptr);
  this->SetTool(nullptr);
  this->SetBoneFile(nullptr);
  this->SetBoneCT(nullptr);
  delete this->Internals;
}

const char* vtkBMSessionSource::GetPauseReason() {
  return this->Internals->PauseReason.c_str();
}

const char* vtkBMSessionSource::GetLastError() {
  return this->Internals->Error.c_str();
}

int vtkBMSessionSource::GetSessionVoxmapResolution() {
  const auto& setup = this->Internals->Setup;
  return setup ? setup->GetScene().voxmapResolution : 0;
}

int vtkBMSessionSource::GetSessionShellResolution() {
  const auto& setup = this->Internals->Setup;
  return setup ? setup->GetScene().shellResolution : 0;
}

bool vtkBMSessionSource::Start() {
  vtkInternals& in = *this->Internals;
  this->Stop();
  in.Session.reset();
  in.Error.clear();
  try {
    const std::string name = this->Scene ? this->Scene : "glenoid";
    bm::Scene scene =
        (std::filesystem::path(name).extension() == ".json" || std::filesystem::exists(name))
            ? bm::Scene::Load(name)
            : bm::Scene::Builtin(name);
    nlohmann::json j = scene.ToJson();
    if (this->ShellResolution > 0)
      j["shell_resolution"] = this->ShellResolution;
    if (this->Tool && *this->Tool) {
      nlohmann::json tool;
      try {
        tool = nlohmann::json::parse(this->Tool);
      } catch (const std::exception& e) {
        throw std::invalid_argument(std::string("the tool specification is not JSON: ") + e.what());
      }
      if (!tool.is_object())
        throw std::invalid_argument("the tool specification must be a JSON object");
      j["tool"] = tool;
    }
    if (this->Method != SCENE_METHOD)
      j["method"] = this->Method == ZHENG ? "zheng" : "lazar";
    const bool fromFile = this->BoneFile && *this->BoneFile;
    if (fromFile) {
      const std::filesystem::path file = std::filesystem::absolute(this->BoneFile);
      if (!std::filesystem::is_regular_file(file))
        throw std::runtime_error("the bone file '" + file.string() + "' does not exist");
      j["bone"] = {{"type", "ct"}, {"ct", {{"voxmap", file.string()}}}};
    }
    if (this->BoneCT && *this->BoneCT) {
      if (fromFile)
        throw std::invalid_argument("set either a bone file or a CT bone, not both");
      nlohmann::json ct;
      try {
        ct = nlohmann::json::parse(this->BoneCT);
      } catch (const std::exception& e) {
        throw std::invalid_argument(std::string("the CT bone description is not JSON: ") +
                                    e.what());
      }
      if (!ct.is_object() || !ct.contains("ct"))
        throw std::invalid_argument("the CT bone description must be a JSON object with \"ct\"");
      j["bone"] = {{"type", "ct"}, {"ct", ct}};
    }
    if (this->OverrideTrial) {
      const Eigen::Vector3d axis(this->Axis[0], this->Axis[1], this->Axis[2]);
      if (!(axis.norm() > 0))
        throw std::invalid_argument("the trial axis is zero");
      j["trial"]["entry_mm"] = {this->Entry[0], this->Entry[1], this->Entry[2]};
      const Eigen::Vector3d unit = axis.normalized();
      j["trial"]["axis"] = {unit[0], unit[1], unit[2]};
    }
    const std::string baseDir = scene.baseDir;
    scene = bm::Scene::FromJson(j);
    scene.baseDir = baseDir;
    // A finer voxmap takes a finer shell along (the scene's grid ratio), unless both are set.
    if (this->VoxmapResolution > 0) {
      if (this->ShellResolution > 0)
        scene.voxmapResolution = this->VoxmapResolution;
      else
        scene = scene.WithVoxmapResolution(this->VoxmapResolution);
    }
#ifdef BM_WITH_IO
    bm::Voxmap bone =
        scene.bone.type == "block"
            ? bm::MakeSceneBlock(scene)
            : bm::MakeCTVoxmap(scene.bone.ct, scene.baseDir, fromFile ? 0 : scene.voxmapResolution);
#else
    if (scene.bone.type != "block")
      throw std::runtime_error("scene '" + scene.name +
                               "' needs CT import, which this build leaves out");
    bm::Voxmap bone = bm::MakeSceneBlock(scene);
#endif
    in.Setup = std::make_unique<bm::MachiningSetup>(scene, std::move(bone));

    const bm::TrialSpec& t = scene.trial;
    const Eigen::Vector3d axis = t.axis.normalized();
    bm::SessionOptions options;
    options.realTime = this->RealTime;
    if (!this->RealTime)
      options.overrunLimit = -1; // frames back to back have no period to overrun
    std::shared_ptr<bm::Device> device;
    if (this->DeviceType == MOUSE) {
      in.Mouse = std::make_shared<bm::ProgrammableDevice>(PositionSourceLimits());
      in.Mouse->SetPose(in.MousePose(this->ToolDepth));
      // A depth step (a wheel click, a typed depth) reaches the tool over frames, at 20 mm/s.
      in.Mouse->SetMaxSpeed(20.0);
      device = in.Mouse;
      options.maxFrames = this->MaxFrames;
    } else if (this->DeviceType == TOUCH) {
      in.Mouse.reset();
      device = std::make_shared<bm::TouchDevice>();
      // The Touch's 3.3 N push becomes the tool's reaming thrust (Docs/Session.md, force scaling).
      options.proxy.coupling.forceScale = bm::kDefaultSessionForceScale;
      // The stylus at the workspace centre holds the tool 10 mm above the entry point.
      options.deviceOffsetMm = t.entry + axis * 10.0;
      options.maxFrames = this->MaxFrames;
    } else {
      in.Mouse.reset();
      bm::ScriptedDeviceOptions o;
      o.mode = bm::ScriptMode::Feed;
      o.startMm = t.entry + axis * t.clearanceMm;
      o.axis = axis;
      o.rotation = in.Setup->ToolRotation();
      o.feedMmPerRev = t.feedMmPerRev;
      o.speedRpm = t.speedRpm;
      o.limits = PositionSourceLimits();
      device = std::make_shared<bm::ScriptedDevice>(o);
      const double depth =
          t.depthMm >= 0 ? t.depthMm : bm::FullEngagementDepth(in.Setup->Tool()) + t.extraDepthMm;
      const double duration = (depth + t.clearanceMm) / (t.feedMmPerRev * t.speedRpm / 60.0);
      options.maxFrames =
          this->MaxFrames >= 0 ? this->MaxFrames : int64_t(std::ceil(duration * options.rateHz));
    }
    in.Session = std::make_unique<bm::HapticSession>(*in.Setup, device, options);

    const nlohmann::json& tool = scene.tool;
    const std::string kind = tool.value("type", "drill");
    in.Tool->SetToolType(kind == "reamer" ? vtkBMToolSource::REAMER
                         : kind == "burr" ? vtkBMToolSource::BURR
                                          : vtkBMToolSource::DRILL);
    nlohmann::json params = tool;
    params.erase("type");
    in.Tool->SetParameters(params.dump().c_str());
    in.Surface.MarkAllDirty();
    in.Fraction.MarkAllDirty();
    in.LastFrame = -1;
    in.History.clear();
    in.NextHistoryS = 0;
    in.Session->Start();
  } catch (const std::exception& e) {
    in.Error = e.what();
    in.Session.reset();
    vtkErrorMacro(<< "cannot start the session: " << in.Error);
    return false;
  }
  this->Modified();
  return true;
}

void vtkBMSessionSource::Pause() {
  if (this->Internals->Session)
    this->Internals->Session->Pause();
}

void vtkBMSessionSource::Resume() {
  if (this->Internals->Session)
    this->Internals->Session->Resume();
}

void vtkBMSessionSource::Stop() {
  if (this->Internals->Session) {
    this->Internals->Session->Stop();
    this->Modified();
  }
}

void vtkBMSessionSource::SetToolDepth(double depthMm) {
  if (this->ToolDepth == depthMm)
    return;
  this->ToolDepth = depthMm;
  if (this->Internals->Mouse && this->Internals->Setup)
    this->Internals->Mouse->SetPose(this->Internals->MousePose(depthMm));
  this->Modified();
}

bool vtkBMSessionSource::SaveBone(const char* path) {
  vtkInternals& in = *this->Internals;
  if (!path || !*path)
    return true; // clearing the property
  if (!in.Setup) {
    in.Error = "no session bone to save: start a session first";
    vtkErrorMacro(<< "cannot save the bone: " << in.Error);
    return false;
  }
  const bool wasRunning = in.Session && in.Session->Snapshot().state == bm::SessionState::Running;
  bool ok = true;
  try {
    if (wasRunning) {
      in.Session->Pause();
      if (!in.Session->WaitUntilPaused(1.0))
        throw std::runtime_error("the session did not pause within 1 s");
    }
    in.Setup->GetEngine().SyncBone();
#ifdef BM_WITH_IO
    bm::SaveVoxmap(in.Setup->Bone(), path);
#else
    throw std::runtime_error("saving voxmaps needs the IO library, which this build leaves out");
#endif
    in.Error.clear();
  } catch (const std::exception& e) {
    in.Error = e.what();
    vtkErrorMacro(<< "cannot save the bone: " << in.Error);
    ok = false;
  }
  if (wasRunning)
    in.Session->Resume();
  return ok;
}

bool vtkBMSessionSource::GetNeedsUpdate() {
  vtkInternals& in = *this->Internals;
  const bool needs = in.Session && in.Session->Snapshot().frame != in.LastFrame;
  if (needs)
    this->Modified(); // so that the pipeline update that follows the poll re-executes
  return needs;
}

int vtkBMSessionSource::RequestData(vtkInformation*, vtkInformationVector**,
                                    vtkInformationVector* outputVector) {
  vtkInternals& in = *this->Internals;
  vtkPolyData* bone = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* tool = vtkPolyData::GetData(outputVector, 1);
  if (!in.Setup || !in.Session)
    return 1; // nothing started yet: empty outputs
  const auto t0 = std::chrono::steady_clock::now();
  const bm::SessionSnapshot s = in.Session->Snapshot();
  in.LastFrame = s.frame;

  // Re-extract the bricks the haptic thread changed since the last update (the voxmap's change
  // generations say which), reading the live voxmap without stopping it. At most
  // kSurfaceBudgetMs of extraction per update: what is left goes first next time, so the view
  // keeps ParaView's 33 ms poll while a large cut catches up over a few refreshes.
  in.Surface.SetTimeBudgetMs(kSurfaceBudgetMs);
  this->BricksUpdated = in.Surface.Update(in.Setup->Bone());
  this->BricksPending = in.Surface.LastUpdate().pending;
  bone->ShallowCopy(in.Surface.GetOutput());

  vtkNew<vtkTransform> pose;
  double m[16] = {0};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      m[4 * r + c] = s.toolRotation(r, c);
    m[4 * r + 3] = s.proxyPositionMm[r];
  }
  m[15] = 1;
  pose->SetMatrix(m);
  vtkNew<vtkTransformPolyDataFilter> place;
  place->SetInputConnection(in.Tool->GetOutputPort());
  place->SetTransform(pose);
  place->Update();
  tool->ShallowCopy(place->GetOutput());

  const bm::TrialSpec& t = in.Setup->GetScene().trial;
  const Eigen::Vector3d tip =
      s.proxyPositionMm +
      s.toolRotation * Eigen::Vector3d(0, 0, bm::ForemostCuttingZ(in.Setup->Tool()));
  this->State = int(s.state);
  in.PauseReason = bm::ToString(s.pauseReason);
  this->Frame = s.frame;
  this->TimeS = s.timeS;
  this->ThrustN = s.thrustN;
  this->TorqueNmm = s.torqueNmm;
  this->RemovedVolumeMm3 = s.removedVolumeMm3;
  this->DepthMm = (t.entry - tip).dot(t.axis.normalized());
  in.DrainHistory(s.toolRotation, this->HistoryStepS, this->HistorySeconds);
  vtkTable::GetData(outputVector, 2)->ShallowCopy(in.HistoryTable);
  if (this->VolumeOutput) {
    in.Fraction.Update(in.Setup->Bone());
    vtkImageData::GetData(outputVector, 3)->ShallowCopy(in.Fraction.GetOutput());
  }
  this->FrameMsP50 = s.timing.p50Ms;
  this->FrameMsP99 = s.timing.p99Ms;
  this->ExtractMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return 1;
}

void vtkBMSessionSource::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scene: " << (this->Scene ? this->Scene : "(none)") << "\n";
  os << indent << "VoxmapResolution: " << this->VoxmapResolution << "\n";
  os << indent << "ShellResolution: " << this->ShellResolution << "\n";
  os << indent << "Tool: " << (this->Tool ? this->Tool : "(the scene's)") << "\n";
  os << indent << "Method: " << this->Method << "\n";
  os << indent << "BoneFile: " << (this->BoneFile ? this->BoneFile : "(the scene's bone)") << "\n";
  os << indent << "BoneCT: " << (this->BoneCT ? this->BoneCT : "(none)") << "\n";
  os << indent << "OverrideTrial: " << this->OverrideTrial << ", entry " << this->Entry[0] << " "
     << this->Entry[1] << " " << this->Entry[2] << " mm, axis " << this->Axis[0] << " "
     << this->Axis[1] << " " << this->Axis[2] << "\n";
  os << indent << "DeviceType: " << this->DeviceType << "\n";
  os << indent << "VolumeOutput: " << this->VolumeOutput << "\n";
  os << indent << "History: " << this->HistorySeconds << " s by " << this->HistoryStepS << " s\n";
  os << indent << "RealTime: " << this->RealTime << "\n";
  os << indent << "MaxFrames: " << this->MaxFrames << "\n";
  os << indent << "ToolDepth: " << this->ToolDepth << " mm\n";
  os << indent << "Frame: " << this->Frame << ", removed " << this->RemovedVolumeMm3 << " mm^3\n";
}
