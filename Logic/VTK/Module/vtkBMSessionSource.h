// vtkBMSessionSource.h - a live machining session as a VTK source: the cut bone and the tool.
//
// Owns a bm::HapticSession (Logic/Session) on a scene (built-in name or scene file): the haptic
// thread cuts the voxmap; this source only reads. Output port 0: the cut bone's surface (world
// mm; the 0.5 fill-fraction iso-surface, re-extracted per brick only where the tool has been
// since the last update, bm::BoneSurface). Output port 1: the tool's surface at the proxy pose
// (world mm; cell data EdgeKind as vtkBMToolSource).
//
// Live source: GetNeedsUpdate() is true when the session ran frames since the last execution, so
// ParaView re-executes it (server-manager hint LiveSource); pvpython polls it through the
// NeedsUpdateInfo property. The haptic thread never waits for this source: it reads the
// session's snapshot (double-buffered, try-lock on the writer side) and the voxmap's fill values
// as they are (a brick read while a frame cuts it shows that frame half done; the next update
// redraws it).
//
// Devices: SCRIPTED feeds the tool along the scene's axis at its feed and speed (a robot-driven
// trial, to its depth); MOUSE is a programmable device whose pose follows SetToolDepth() (mm of
// the foremost cutting point below the scene's entry point along its axis), the mouse proxy of the
// panel for users without a Touch.
//
// Units: mm, N, N mm, s, ms, mm^3.
#pragma once

#include "BMVTKLogicModule.h" // for the export macro
#include "vtkPolyDataAlgorithm.h"

class BMVTKLOGIC_EXPORT vtkBMSessionSource : public vtkPolyDataAlgorithm {
public:
  static vtkBMSessionSource* New();
  vtkTypeMacro(vtkBMSessionSource, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum DeviceTypes { SCRIPTED = 0, MOUSE = 1 };

  ///@{
  /// The scene: a built-in name ("glenoid", "drilling") or a scene file (.json). Default
  /// "glenoid". Takes effect at the next Start().
  vtkSetStringMacro(Scene);
  vtkGetStringMacro(Scene);
  ///@}
  ///@{
  /// Voxmap and shell resolutions (cells along the longest side); 0 (default) keeps the scene's.
  vtkSetClampMacro(VoxmapResolution, int, 0, 4096);
  vtkGetMacro(VoxmapResolution, int);
  vtkSetClampMacro(ShellResolution, int, 0, 4096);
  vtkGetMacro(ShellResolution, int);
  ///@}
  ///@{
  /// SCRIPTED (default) or MOUSE.
  vtkSetClampMacro(DeviceType, int, SCRIPTED, MOUSE);
  vtkGetMacro(DeviceType, int);
  ///@}
  ///@{
  /// Real time (default on: frames at the session rate, 1 kHz) or frames back to back (tests).
  vtkSetMacro(RealTime, bool);
  vtkGetMacro(RealTime, bool);
  vtkBooleanMacro(RealTime, bool);
  ///@}
  ///@{
  /// Pause after this many frames (< 0, default: the scripted trial's length; no limit with MOUSE).
  vtkSetMacro(MaxFrames, vtkIdType);
  vtkGetMacro(MaxFrames, vtkIdType);
  ///@}
  ///@{
  /// MOUSE device: depth of the tool's foremost cutting point below the entry point, mm (negative:
  /// above). Any time; the haptic thread picks it up at its next frame. Default -2 mm.
  void SetToolDepth(double depthMm);
  vtkGetMacro(ToolDepth, double);
  ///@}

  /// Builds the scene (imports its bone), starts the session. Errors go to vtkErrorMacro and
  /// GetLastError(); returns false then.
  bool Start();
  void Pause();
  void Resume();
  /// Stops the session; the cut bone stays for display and saving.
  void Stop();
  /// Saves the cut bone as a voxmap file (.nrrd or .mha). Returns false (GetLastError()) on error.
  bool SaveBone(const char* path);

  /// True when the session ran frames since the last execution (ParaView's live-source poll);
  /// then also marks this source modified, so the update that follows re-executes it.
  bool GetNeedsUpdate();
  ///@{
  /// The session as of the last execution.
  /// State: 0 idle, 1 running, 2 paused, 3 stopped.
  vtkGetMacro(State, int);
  vtkGetMacro(Frame, vtkIdType);
  vtkGetMacro(TimeS, double);
  vtkGetMacro(ThrustN, double);
  vtkGetMacro(TorqueNmm, double);
  vtkGetMacro(RemovedVolumeMm3, double);
  /// Depth of the proxy's foremost cutting point below the entry point along the axis, mm.
  vtkGetMacro(DepthMm, double);
  vtkGetMacro(FrameMsP50, double);
  vtkGetMacro(FrameMsP99, double);
  /// Bricks re-extracted by the last execution, and its time, ms.
  vtkGetMacro(BricksUpdated, int);
  vtkGetMacro(ExtractMs, double);
  const char* GetLastError();
  ///@}

protected:
  vtkBMSessionSource();
  ~vtkBMSessionSource() override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  char* Scene = nullptr;
  int VoxmapResolution = 0;
  int ShellResolution = 0;
  int DeviceType = SCRIPTED;
  bool RealTime = true;
  vtkIdType MaxFrames = -1;
  double ToolDepth = -2.0;
  int State = 0;
  vtkIdType Frame = 0;
  double TimeS = 0, ThrustN = 0, TorqueNmm = 0, RemovedVolumeMm3 = 0, DepthMm = 0;
  double FrameMsP50 = 0, FrameMsP99 = 0, ExtractMs = 0;
  int BricksUpdated = 0;

private:
  vtkBMSessionSource(const vtkBMSessionSource&) = delete;
  void operator=(const vtkBMSessionSource&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};
