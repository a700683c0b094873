// vtkBMSessionSource.h - a live machining session as a VTK source: the cut bone and the tool.
//
// Owns a bm::HapticSession (Logic/Session) on a scene (built-in name or scene file): the haptic
// thread cuts the voxmap; this source only reads. Output port 0: the cut bone's surface (world
// mm; the 0.5 fill-fraction iso-surface, re-extracted per brick only where the voxmap changed
// since the last update, bm::BoneSurface). Output port 1: the tool's surface at the proxy pose
// (world mm; cell data EdgeKind as vtkBMToolSource). Output port 2: the session's recent history
// as a vtkTable (columns time_s, thrust_N, torque_Nmm, frame_ms, depth_mm, feed_mm_per_rev; one
// row per HistoryStepS of session time over the last HistorySeconds; a step of one period keeps
// every frame), drained from the session's record
// ring when this source executes, for live charts. Output port 3: with VolumeOutput on, the cut
// bone as vtkImageData (point data BoneFraction, 0..1, at the voxel centres, world mm) for volume
// rendering; empty otherwise.
//
// Live source: GetNeedsUpdate() is true when the session ran frames (or paused, or resumed) since
// the last execution, so ParaView re-executes it (server-manager hint LiveSource); pvpython polls
// it through the NeedsUpdateInfo property. The haptic thread never waits for this source: it
// reads the session's snapshot (double-buffered, try-lock on the writer side) and the voxmap's
// fills through atomic loads, after marking their bricks seen (bm::Voxmap::SeenBrickGeneration):
// a brick read while a frame cuts it shows that frame half done and is re-extracted at the next
// update.
//
// The session is built as every session is (bm::ApplyOverrides, bm::BuildSession; Docs/Session.md,
// "Building a session"). Devices: SCRIPTED feeds the tool along the scene's axis at its feed and
// speed from the trial's clearance above the entry (a robot-driven trial, to its depth,
// bm::SessionDevice::Robot); MOUSE is a programmable device whose pose follows SetToolDepth() (mm
// of the foremost cutting point below the scene's entry point along its axis), the mouse proxy of
// the panel for users without a Touch; TOUCH is a 3D Systems Touch through OpenHaptics
// (bm::TouchDevice, libHD loaded at Start(); ProbeTouch() says whether it can be opened and why
// not), its workspace centre placed 10 mm above the entry point along the axis; HAND is the
// scripted hand on a simulated Touch (bm::SessionDevice::Scripted, bm::ScriptMode::Hand: a 2.5 N
// push rising over 0.5 s with lateral tremor, the tool's force scale, bm::SessionForceScale; 60 s
// session, the benchmark's hand-like trial, unless MaxFrames says otherwise), for tests and
// demonstrations without a device.
//
// The scene's tool, force model and bone can be overridden: SetTool() (a tool specification, as
// vtkBMToolSource::GetToolSpecification() gives it), SetMethod() and SetBoneFile() (a voxmap
// saved by SaveBone(), to go on machining a saved bone).
//
// Units: mm, N, N mm, s, ms, mm^3.
#pragma once

#include "BMVTKLogicModule.h" // for the export macro
#include "vtkPolyDataAlgorithm.h"

#ifndef __VTK_WRAP__
#include <string>
#endif

class vtkImageData;
class vtkTable;

class BMVTKLOGIC_EXPORT vtkBMSessionSource : public vtkPolyDataAlgorithm {
public:
  static vtkBMSessionSource* New();
  vtkTypeMacro(vtkBMSessionSource, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum DeviceTypes { SCRIPTED = 0, MOUSE = 1, TOUCH = 2, HAND = 3 };
  /// Force model: the scene's (default), Lazar's oblique cutting (Faieghi et al.) or Zheng's.
  enum MethodTypes { SCENE_METHOD = 0, LAZAR = 1, ZHENG = 2 };

  ///@{
  /// The scene: a built-in name ("glenoid", "drilling") or a scene file (.json). Default
  /// "glenoid". Takes effect at the next Start().
  vtkSetStringMacro(Scene);
  vtkGetStringMacro(Scene);
  ///@}
  ///@{
  /// Voxmap and shell resolutions (cells along the longest side). Both 0 (default): chosen for
  /// the session (bmSessionGrid.h: no finer than the scene's, this machine's measured limit with
  /// the live view, and a CT bone's spacing; the engine's threads from the same measurement).
  /// A voxmap resolution set without a shell resolution scales the scene's shell alike
  /// (bm::Scene::WithVoxmapResolution: the grids keep their ratio, 2:1 in the built-in scenes).
  vtkSetClampMacro(VoxmapResolution, int, 0, 4096);
  vtkGetMacro(VoxmapResolution, int);
  vtkSetClampMacro(ShellResolution, int, 0, 4096);
  vtkGetMacro(ShellResolution, int);
  ///@}
  ///@{
  /// The tool: a JSON tool specification {"type": "drill" | "reamer" | "burr", parameters...}
  /// (bm::MakeTool's keys, units in the key names, e.g. "radius_mm"), replacing the scene's.
  /// Empty (default): the scene's tool. Takes effect at the next Start(), which fails naming the
  /// bad field when the specification is invalid.
  vtkSetStringMacro(Tool);
  vtkGetStringMacro(Tool);
  ///@}
  ///@{
  /// Force model: SCENE_METHOD (default), LAZAR or ZHENG. Takes effect at the next Start().
  vtkSetClampMacro(Method, int, SCENE_METHOD, ZHENG);
  vtkGetMacro(Method, int);
  ///@}
  ///@{
  /// A voxmap file (.nrrd or .mha, as SaveBone() writes) to machine instead of the scene's bone,
  /// e.g. a bone cut and saved earlier. Empty (default): the scene's bone. The file's own
  /// resolution is kept (VoxmapResolution does not resample it). Takes effect at the next Start().
  vtkSetStringMacro(BoneFile);
  vtkGetStringMacro(BoneFile);
  ///@}
  ///@{
  /// With a BoneFile that carries the trial it was cut on (SaveBone saves the session's entry,
  /// axis and tool with the bone) and OverrideTrial off, that trial replaces the scene's (and its
  /// tool the scene's, unless Tool is set), so that a session started again from a saved bone
  /// goes on where it was cut, with the tool that cut it (default on). Off: the scene's trial and
  /// tool (a plan's step scene carries its own). Takes effect at the next Start().
  vtkSetMacro(BoneFileTrial, bool);
  vtkGetMacro(BoneFileTrial, bool);
  vtkBooleanMacro(BoneFileTrial, bool);
  ///@}
  ///@{
  /// A CT bone to machine instead of the scene's: the "ct" description of a scene's bone as JSON
  /// ({"ct": folder-or-file, "threshold": HU, "roi": [x0, y0, z0, x1, y1, z1] mm}, as
  /// vtkBMCTBoneSource::GetBoneSpecification() gives it), imported at VoxmapResolution (or the
  /// scene's). Empty (default): the scene's bone. Start() refuses both BoneFile and BoneCT set.
  vtkSetStringMacro(BoneCT);
  vtkGetStringMacro(BoneCT);
  ///@}
  ///@{
  /// With OverrideTrial on (default off), the trial's entry point (world mm, where the axis enters
  /// the bone) and axis (world, from the bone out toward the shank; normalized) replace the
  /// scene's; the feed, speed, clearance and depth stay the scene's. Takes effect at Start().
  vtkSetMacro(OverrideTrial, bool);
  vtkGetMacro(OverrideTrial, bool);
  vtkBooleanMacro(OverrideTrial, bool);
  vtkSetVector3Macro(Entry, double);
  vtkGetVector3Macro(Entry, double);
  vtkSetVector3Macro(Axis, double);
  vtkGetVector3Macro(Axis, double);
  ///@}
  ///@{
  /// SCRIPTED (default: the robot's feed), MOUSE, TOUCH or HAND (the scripted hand).
  vtkSetClampMacro(DeviceType, int, SCRIPTED, HAND);
  vtkGetMacro(DeviceType, int);
  ///@}
  ///@{
  /// Output port 3 (the cut bone as an image for volume rendering) on or off (default off: the
  /// image holds one float per voxel; an update copies the voxmap's changed 8^3 bricks,
  /// bm::BoneFractionImage).
  vtkSetMacro(VolumeOutput, bool);
  vtkGetMacro(VolumeOutput, bool);
  vtkBooleanMacro(VolumeOutput, bool);
  ///@}
  ///@{
  /// History kept on output port 2: the last HistorySeconds of session time (default 10 s,
  /// clamped to [0.1, 600]), one row per HistoryStepS (default 0.01 s, clamped to [0.001, 1]).
  vtkSetClampMacro(HistorySeconds, double, 0.1, 600.0);
  vtkGetMacro(HistorySeconds, double);
  vtkSetClampMacro(HistoryStepS, double, 0.001, 1.0);
  vtkGetMacro(HistoryStepS, double);
  ///@}
  ///@{
  /// Real time (default on: frames at the session rate, 1 kHz) or frames back to back (tests).
  vtkSetMacro(RealTime, bool);
  vtkGetMacro(RealTime, bool);
  vtkBooleanMacro(RealTime, bool);
  ///@}
  ///@{
  /// Pause after this many frames (< 0, default: the scripted trial's length, 60 s with HAND; no
  /// limit with MOUSE or TOUCH).
  vtkSetMacro(MaxFrames, vtkIdType);
  vtkGetMacro(MaxFrames, vtkIdType);
  ///@}
  ///@{
  /// MOUSE device: depth of the tool's foremost cutting point below the entry point, mm (negative:
  /// above). Any time; the haptic thread picks it up at its next frame. Default -2 mm.
  void SetToolDepth(double depthMm);
  vtkGetMacro(ToolDepth, double);
  ///@}
  ///@{
  /// Force scale, tool N per device N, in [1e-3, 1000] (bm::CheckForceScale); 0 (default): the
  /// device's (the tool's, bm::SessionForceScale, for a Touch or the scripted hand; 1 for the
  /// mouse proxy). Takes effect at
  /// the next Start(), which fails naming the range for a value outside it.
  vtkSetMacro(ForceScale, double);
  vtkGetMacro(ForceScale, double);
  ///@}

  /// Voxmap and point-shell resolutions (cells along the longest side) of the session last
  /// started: what the scene, VoxmapResolution and ShellResolution came to. 0 before Start().
  int GetSessionVoxmapResolution();
  int GetSessionShellResolution();
  /// Engine threads of the session last started (0 before Start()).
  int GetSessionThreads();
  /// How the session last started chose its resolutions, in words ("" when they were set).
  const char* GetSessionGridReason();
  /// The trial of the session last started: its entry point (world mm) and axis (unit, from the
  /// bone out), what a restart from its saved bone must keep. False (nothing written) before
  /// Start().
  bool GetSessionTrial(double entryMm[3], double axis[3]);
  /// The same entry point (world mm) and axis (unit), for information properties; zeros before
  /// Start().
  double* GetSessionEntry() VTK_SIZEHINT(3);
  double* GetSessionAxis() VTK_SIZEHINT(3);
  /// Why the session's tool starts further out along its axis than the scene's clearance (bone
  /// lay inside it there; bm::StartLiftMm), "" when it starts at the scene's.
  const char* GetSessionStartNote();
  /// Where that trial came from: "the scene's", "set" (OverrideTrial) or "the bone file's" (the
  /// trial saved with BoneFile); "" before Start().
  const char* GetSessionTrialSource();
  /// World bounds (x0, x1, y0, y1, z0, z1 mm) of the session's bone voxmap, what a view frames
  /// before the first surface is extracted; all 0 before Start().
  vtkGetVector6Macro(BoneBounds, double);

  /// Builds the scene (imports its bone), starts the session. Errors go to vtkErrorMacro and
  /// GetLastError(); returns false then. With StartInBackground the bone is built on a worker
  /// thread and Start() returns at once (false only for a request refused before building):
  /// poll GetStarting() and GetStartProgress(), then call FinishStart().
  bool Start();
  ///@{
  /// Start() builds the bone on a worker thread, so that a GUI stays responsive for the seconds a
  /// glenoid's import takes (default false: on the calling thread, as scripts expect).
  vtkSetMacro(StartInBackground, bool);
  vtkGetMacro(StartInBackground, bool);
  vtkBooleanMacro(StartInBackground, bool);
  ///@}
  /// Whether a background start is still building its bone.
  bool GetStarting();
  /// The background start's progress, 0..1, and its stage in words ("" before any).
  double GetStartProgress();
  const char* GetStartStage();
  /// After a background start has built its bone (GetStarting() false): installs the session and
  /// starts it. False when the build failed or was cancelled (Stop()), GetLastError() saying why,
  /// or when it is still building. Call it on the thread that owns the source.
  bool FinishStart();
  void Pause();
  void Resume();
  /// Stops the session; the cut bone stays for display and saving. A background start still
  /// building is cancelled (its worker joined) and FinishStart() then reports it.
  void Stop();
  /// Saves the cut bone as a voxmap file (.nrrd or .mha; atomic: a temporary file renamed over
  /// the target when complete, so a failure leaves no partial file), with the session's trial
  /// (bm::VoxmapTrial: a start from the file goes on there, see BoneFileTrial). A running session
  /// is paused while the bone is written and resumed after. Returns false (GetLastError()) on
  /// error: no session bone, a refused extension or folder, a write failure. An empty path does
  /// nothing (returns true), so the server-manager property can be cleared.
  bool SaveBone(const char* path);
  /// Whether the session keeps a copy of its bone as it was at Start (default off: it costs a
  /// voxmap's memory), for SaveInitialBone: a plan's result compares the bone before its steps
  /// with the bone after them.
  vtkSetMacro(KeepInitialBone, bool);
  vtkGetMacro(KeepInitialBone, bool);
  /// Saves the bone as it was when the session started (KeepInitialBone on), as SaveBone saves
  /// (atomic, .nrrd or .mha). Returns false (GetLastError()) when no initial bone was kept or the
  /// write fails; an empty path does nothing (returns true).
  bool SaveInitialBone(const char* path);

#ifndef __VTK_WRAP__
  /// Whether a Touch can be opened now: starts and stops a bm::TouchDevice (libHD from
  /// $BM_LIBHD or "libHD.so"). Returns "" when it can, else why not (the library, a missing
  /// symbol, no device), as the device's own error says.
  static std::string ProbeTouch();
#endif
  /// ProbeTouch()'s answer, probed at this call; "" when a Touch can be opened.
  const char* GetTouchStatus();

  /// True when the session ran frames, or changed its state or pause reason, since the last
  /// execution (ParaView's live-source poll; a pause runs no frame but must still be shown); then
  /// also marks this source modified, so the update that follows re-executes it.
  bool GetNeedsUpdate();
  ///@{
  /// The session as of the last execution.
  /// State: 0 idle, 1 running, 2 paused, 3 stopped.
  vtkGetMacro(State, int);
  /// Why the session paused: "none", "user", "finished" (frame limit or the scripted trial's
  /// end), "overrun" (too many frames over the period), "device error", "device not answering"
  /// or "frame error" (bm::PauseReason).
  const char* GetPauseReason();
  vtkGetMacro(Frame, vtkIdType);
  vtkGetMacro(TimeS, double);
  vtkGetMacro(ThrustN, double);
  vtkGetMacro(TorqueNmm, double);
  vtkGetMacro(RemovedVolumeMm3, double);
  /// Depth of the proxy's foremost cutting point below the entry point along the axis, mm.
  vtkGetMacro(DepthMm, double);
  vtkGetMacro(FrameMsP50, double);
  vtkGetMacro(FrameMsP99, double);
  /// The force scale the running session uses (tool N per device N): ForceScale, or the device's
  /// when that is 0 (bm::SessionForceScale for a hand on a Touch); 0 before the first Start.
  vtkGetMacro(ForceScaleInUse, double);
  /// Bricks re-extracted by the last execution, and its time, ms.
  vtkGetMacro(BricksUpdated, int);
  /// Changed bricks the last execution left for the next (its extraction time budget, 8 ms).
  vtkGetMacro(BricksPending, int);
  vtkGetMacro(ExtractMs, double);
  const char* GetLastError();
  ///@}
  /// The history table (output port 2) and the bone image (output port 3) of the last
  /// execution.
  vtkTable* GetHistory();
  vtkImageData* GetBoneImage();

protected:
  vtkBMSessionSource();
  ~vtkBMSessionSource() override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  /// Port 3's whole extent, origin and spacing (the voxmap's grid), which image consumers such
  /// as ParaView's volume representation need before they request data.
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
                         vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  char* Scene = nullptr;
  char* Tool = nullptr;
  char* BoneFile = nullptr;
  bool BoneFileTrial = true;
  bool KeepInitialBone = false;
  char* BoneCT = nullptr;
  bool OverrideTrial = false;
  double Entry[3] = {0, 0, 0};
  double Axis[3] = {0, 0, 1};
  int Method = SCENE_METHOD;
  bool VolumeOutput = false;
  double HistorySeconds = 10.0;
  double HistoryStepS = 0.01;
  int VoxmapResolution = 0;
  int ShellResolution = 0;
  int DeviceType = SCRIPTED;
  bool RealTime = true;
  bool StartInBackground = false;
  double BoneBounds[6] = {0, 0, 0, 0, 0, 0};
  double SessionEntry[3] = {0, 0, 0}, SessionAxis[3] = {0, 0, 0}; ///< GetSessionEntry/Axis
  vtkIdType MaxFrames = -1;
  double ToolDepth = -2.0;
  double ForceScale = 0, ForceScaleInUse = 0;
  int State = 0;
  vtkIdType Frame = 0;
  double TimeS = 0, ThrustN = 0, TorqueNmm = 0, RemovedVolumeMm3 = 0, DepthMm = 0;
  double FrameMsP50 = 0, FrameMsP99 = 0, ExtractMs = 0;
  int BricksUpdated = 0, BricksPending = 0;

private:
  vtkBMSessionSource(const vtkBMSessionSource&) = delete;
  void operator=(const vtkBMSessionSource&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};
