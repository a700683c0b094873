// vtkBMSessionSource.cxx - see vtkBMSessionSource.h.
#include "vtkBMSessionSource.h"

#include "bmBoneFractionImage.h"
#include "bmBoneSurface.h"
#ifdef BM_WITH_IO
#include "bmVoxmapFile.h"
#endif
#include "bmHapticSession.h"
#include "bmMachiningSetup.h"
#include "bmProgrammableDevice.h"
#include "bmScene.h"
#include "bmSceneOverrides.h"
#include "bmSessionBuilder.h"
#include "bmTouchDevice.h"
#include "bmTouchProbe.h"
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
#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {
/// Most time one update spends re-extracting the bone's surface, ms (ParaView polls every 33 ms;
/// a quarter of that keeps the haptic frame as fast as without the view on two busy cores).
constexpr double kSurfaceBudgetMs = 8.0;
} // namespace

class vtkBMSessionSource::vtkInternals {
public:
  std::unique_ptr<bm::MachiningSetup> Setup;
  std::unique_ptr<bm::Voxmap> InitialBone; ///< the bone at Start (KeepInitialBone)
  std::shared_ptr<bm::ProgrammableDevice> Mouse;
  std::unique_ptr<bm::HapticSession> Session;
  std::string GridReason;  ///< BuiltSession::gridReason of the session last started
  std::string TrialSource; ///< where the trial of the session last started came from
  std::string StartNote;   ///< BuiltSession::startNote of the session last started
  /// The cut bone's surface, in BoneSurface's default bricks of 8 voxels (one per voxmap
  /// generation brick: a cut re-extracts only the thin layer it changed).
  bm::BoneSurface Surface;
  vtkNew<vtkBMToolSource> Tool;
  int64_t LastFrame = -1;
  /// State and pause reason of the last execution: a pause publishes a new state without a new
  /// frame, and the output must still be re-executed to show it.
  bm::SessionState LastState = bm::SessionState::Idle;
  bm::PauseReason LastReason = bm::PauseReason::None;
  std::string Error;
  std::string TouchStatus;
  std::string PauseReason = "none";
  /// History rows (time_s, thrust_N, torque_Nmm, frame_ms, depth_mm, feed_mm_per_rev), oldest
  /// first, and the session time of the next row to keep.
  std::deque<std::array<double, 6>> History;
  double NextHistoryS = 0;
  std::vector<bm::FrameRecord> Records; ///< drained from the session, reused
  vtkNew<vtkTable> HistoryTable;
  /// The cut bone's fill fractions for volume rendering, copied per changed brick.
  bm::BoneFractionImage Fraction;

  /// A background start (StartInBackground): the worker building the session, whether it still
  /// runs, a cancel request its progress callback answers, its progress and stage, and what it
  /// built (or why it failed), handed over under BuildMutex.
  std::thread Builder;
  std::atomic<bool> Building{false}, CancelBuild{false};
  std::atomic<double> BuildProgress{0};
  std::mutex BuildMutex;
  std::string BuildStage, StageCopy, BuildError;
  std::unique_ptr<bm::BuiltSession> Built;
  bm::Scene PendingScene;
  /// Cancels and joins the background start's worker, if any.
  void JoinBuilder() {
    this->CancelBuild = true;
    if (this->Builder.joinable())
      this->Builder.join();
    this->Building = false;
  }

#ifdef BM_WITH_IO
  /// The header fields that save the session's trial with its bone (bm::VoxmapTrialFields).
  std::vector<std::pair<std::string, std::string>> TrialFields() const {
    const bm::Scene& scene = this->Setup->GetScene();
    const bm::TrialSpec& t = scene.trial;
    const Eigen::Vector3d a = t.axis.normalized();
    return bm::VoxmapTrialFields(bm::VoxmapTrial{
        {t.entry(0), t.entry(1), t.entry(2)}, {a(0), a(1), a(2)}, scene.ToJson()["tool"].dump()});
  }
#endif

  /// Depth (mm) of the foremost cutting point of a tool at (pos, rot) below the entry point.
  double Depth(const Eigen::Vector3d& pos, const Eigen::Matrix3d& rot) const {
    return bm::ToolDepthMm(*this->Setup, pos, rot);
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
          {r.timeS, r.thrustN, r.torqueNmm, r.frameMs, this->Depth(proxy, rot), r.feedMmPerRev});
      this->NextHistoryS = r.timeS + stepS;
    }
    while (!this->History.empty() && this->History.front()[0] < this->History.back()[0] - keepS)
      this->History.pop_front();
    static const char* const names[6] = {"time_s",   "thrust_N", "torque_Nmm",
                                         "frame_ms", "depth_mm", "feed_mm_per_rev"};
    vtkNew<vtkTable> table;
    for (int c = 0; c < 6; ++c) {
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
    return bm::ToolPoseAtDepth(*this->Setup, depthMm);
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
  // In a child process, every step a session takes at zero force (force output, the servo loop):
  // a faulting driver cannot take ParaView down.
  const bm::TouchProbeResult r = bm::ProbeTouch(5.0);
  return r.ready ? std::string() : r.message;
}

const char* vtkBMSessionSource::GetTouchStatus() {
  this->Internals->TouchStatus = ProbeTouch();
  return this->Internals->TouchStatus.c_str();
}

vtkBMSessionSource::~vtkBMSessionSource() {
  this->Internals->JoinBuilder();
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

int vtkBMSessionSource::GetSessionThreads() {
  const auto& setup = this->Internals->Setup;
  return setup ? setup->GetScene().threads : 0;
}

bool vtkBMSessionSource::GetSessionTrial(double entryMm[3], double axis[3]) {
  const auto& setup = this->Internals->Setup;
  if (!setup)
    return false;
  const bm::TrialSpec& t = setup->GetScene().trial;
  const Eigen::Vector3d a = t.axis.normalized();
  for (int i = 0; i < 3; ++i) {
    entryMm[i] = t.entry(i);
    axis[i] = a(i);
  }
  return true;
}

const char* vtkBMSessionSource::GetSessionGridReason() {
  return this->Internals->GridReason.c_str();
}

double* vtkBMSessionSource::GetSessionEntry() {
  this->GetSessionTrial(this->SessionEntry, this->SessionAxis);
  return this->SessionEntry;
}

double* vtkBMSessionSource::GetSessionAxis() {
  this->GetSessionTrial(this->SessionEntry, this->SessionAxis);
  return this->SessionAxis;
}

const char* vtkBMSessionSource::GetSessionStartNote() {
  return this->Internals->StartNote.c_str();
}

const char* vtkBMSessionSource::GetSessionTrialSource() {
  return this->Internals->TrialSource.c_str();
}

bool vtkBMSessionSource::Start() {
  vtkInternals& in = *this->Internals;
  this->Stop();
  in.JoinBuilder();
  in.Session.reset();
  in.Built.reset();
  in.Error.clear();
  in.BuildError.clear();
  in.BuildStage.clear();
  in.BuildProgress = 0;
  bm::SessionRequest request;
  try {
    bm::SceneOverrides o;
    o.voxmapResolution = this->VoxmapResolution;
    o.shellResolution = this->ShellResolution;
    o.toolJson = this->Tool ? this->Tool : "";
    if (this->Method != SCENE_METHOD)
      o.method = this->Method == ZHENG ? "zheng" : "lazar";
    o.boneFile = this->BoneFile ? this->BoneFile : "";
    o.boneCTJson = this->BoneCT ? this->BoneCT : "";
    in.TrialSource = "the scene's";
    if (this->OverrideTrial) {
      o.entryMm = Eigen::Vector3d(this->Entry[0], this->Entry[1], this->Entry[2]);
      o.axis = Eigen::Vector3d(this->Axis[0], this->Axis[1], this->Axis[2]);
      in.TrialSource = "set";
    } else if (!o.boneFile.empty() && this->BoneFileTrial) {
#ifdef BM_WITH_IO
      // A bone saved from a session goes on where it was cut (SaveBone saves the trial with it).
      if (const auto saved = bm::LoadVoxmapTrial(o.boneFile)) {
        o.entryMm = Eigen::Vector3d(saved->entryMm.data());
        o.axis = Eigen::Vector3d(saved->axis.data());
        if (o.toolJson.empty()) // the tool that cut it, unless another is asked for
          o.toolJson = saved->toolJson;
        in.TrialSource = "the bone file's";
      }
#endif
    }
    in.PendingScene =
        bm::ApplyOverrides(bm::ResolveScene(this->Scene ? this->Scene : "glenoid"), o);

    request.device = this->DeviceType == MOUSE   ? bm::SessionDevice::Mouse
                     : this->DeviceType == TOUCH ? bm::SessionDevice::Touch
                     : this->DeviceType == HAND  ? bm::SessionDevice::Scripted
                                                 : bm::SessionDevice::Robot;
    if (this->DeviceType == HAND) {
      request.mode = bm::ScriptMode::Hand;
      if (this->MaxFrames < 0)
        request.durationS = 60; // the benchmark's hand-like trial (Docs/RealTime.md)
    }
    if (this->DeviceType == TOUCH) {
      // The driver is loaded into ParaView only after it ran in a child process (ProbeTouch).
      const std::string why = ProbeTouch();
      if (!why.empty())
        throw std::runtime_error(why);
    }
    request.realTime = this->RealTime;
    request.maxFrames = this->MaxFrames >= 0 ? this->MaxFrames : -1;
    request.mouseDepthMm = this->ToolDepth;
    request.forceScale = this->ForceScale;
    // Resolutions left to the session: what it needs with the live view this source refreshes.
    request.chooseGrid = this->VoxmapResolution == 0 && this->ShellResolution == 0;
    request.liveView = true;
    bm::ValidateSessionRequest(request);
    if (!this->StartInBackground) {
      in.Built = std::make_unique<bm::BuiltSession>(bm::BuildSession(in.PendingScene, request));
      return this->FinishStart();
    }
  } catch (const std::exception& e) {
    in.Error = e.what();
    vtkErrorMacro(<< "cannot start the session: " << in.Error);
    return false;
  }
  // The bone on a worker; FinishStart() installs what it built, on this thread.
  in.CancelBuild = false;
  in.Building = true;
  in.Builder = std::thread([&in, request, scene = in.PendingScene]() {
    auto progress = [&in](double fraction, const std::string& stage) {
      in.BuildProgress = fraction;
      {
        std::lock_guard<std::mutex> lock(in.BuildMutex);
        in.BuildStage = stage;
      }
      return !in.CancelBuild.load();
    };
    std::unique_ptr<bm::BuiltSession> built;
    std::string error;
    try {
      built = std::make_unique<bm::BuiltSession>(bm::BuildSession(scene, request, progress));
      if (in.CancelBuild)
        error = "cancelled";
    } catch (const std::exception& e) {
      error = in.CancelBuild ? "cancelled" : e.what();
    }
    {
      std::lock_guard<std::mutex> lock(in.BuildMutex);
      in.Built = error.empty() ? std::move(built) : nullptr;
      in.BuildError = error;
    }
    in.Building = false;
  });
  return true;
}

bool vtkBMSessionSource::GetStarting() {
  return this->Internals->Building.load();
}

double vtkBMSessionSource::GetStartProgress() {
  return this->Internals->BuildProgress.load();
}

const char* vtkBMSessionSource::GetStartStage() {
  vtkInternals& in = *this->Internals;
  std::lock_guard<std::mutex> lock(in.BuildMutex);
  in.StageCopy = in.BuildStage;
  return in.StageCopy.c_str();
}

bool vtkBMSessionSource::FinishStart() {
  vtkInternals& in = *this->Internals;
  if (in.Building)
    return false;
  if (in.Builder.joinable())
    in.Builder.join();
  std::unique_ptr<bm::BuiltSession> built;
  {
    std::lock_guard<std::mutex> lock(in.BuildMutex);
    built = std::move(in.Built);
    if (!in.BuildError.empty())
      in.Error = in.BuildError;
  }
  if (!built) {
    if (in.Error.empty())
      in.Error = "no session was built (call Start() first)";
    return false;
  }
  try {
    in.GridReason = built->gridReason;
    in.StartNote = built->startNote;
    this->ForceScaleInUse = built->options.proxy.coupling.forceScale;
    in.Setup = std::move(built->setup);
    in.InitialBone.reset();
    if (this->KeepInitialBone)
      in.InitialBone = std::make_unique<bm::Voxmap>(in.Setup->Bone());
    in.Mouse = built->mouse;
    in.Session = std::make_unique<bm::HapticSession>(*in.Setup, built->device, built->options);
    const bm::Box3 box = in.Setup->Bone().Bounds();
    for (int a = 0; a < 3; ++a) {
      this->BoneBounds[2 * a] = box.lo[size_t(a)];
      this->BoneBounds[2 * a + 1] = box.hi[size_t(a)];
    }

    const nlohmann::json& tool = in.PendingScene.tool;
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
    in.LastState = bm::SessionState::Idle;
    in.LastReason = bm::PauseReason::None;
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
  if (this->Internals->Building)
    this->Internals->JoinBuilder(); // cancelled: FinishStart() reports it
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
    bm::SaveVoxmap(in.Setup->Bone(), path, {}, in.TrialFields());
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

bool vtkBMSessionSource::SaveInitialBone(const char* path) {
  vtkInternals& in = *this->Internals;
  if (!path || !*path)
    return true; // clearing the property
  try {
    if (!in.InitialBone)
      throw std::runtime_error("no initial bone was kept: turn KeepInitialBone on before Start");
#ifdef BM_WITH_IO
    bm::SaveVoxmap(*in.InitialBone, path, {}, in.TrialFields());
#else
    throw std::runtime_error("saving voxmaps needs the IO library, which this build leaves out");
#endif
    in.Error.clear();
    return true;
  } catch (const std::exception& e) {
    in.Error = e.what();
    vtkErrorMacro(<< "cannot save the initial bone: " << in.Error);
    return false;
  }
}

bool vtkBMSessionSource::GetNeedsUpdate() {
  vtkInternals& in = *this->Internals;
  bool needs = false;
  if (in.Session) {
    const bm::SessionSnapshot s = in.Session->Snapshot();
    needs = s.frame != in.LastFrame || s.state != in.LastState || s.pauseReason != in.LastReason;
  }
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
  in.LastState = s.state;
  in.LastReason = s.pauseReason;

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

  this->State = int(s.state);
  in.PauseReason = bm::ToString(s.pauseReason);
  this->Frame = s.frame;
  this->TimeS = s.timeS;
  this->ThrustN = s.thrustN;
  this->TorqueNmm = s.torqueNmm;
  this->RemovedVolumeMm3 = s.removedVolumeMm3;
  this->DepthMm = in.Depth(s.proxyPositionMm, s.toolRotation);
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
