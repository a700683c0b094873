// pqBMDockWindow.h - the BoneMachining dock in ParaView: hosts the qBMPanel (Widgets/) and turns
// its sections' requests into ParaView pipeline actions. Glue only; the panel and the logic do
// the rest (Docs/Plugin.md).
#pragma once

#include <QDockWidget>
#include <QElapsedTimer>
#include <QPoint>
#include <QPointer>
#include <QVector>

#include <functional>

#include "vtkType.h"

class pqPipelineSource;
class vtkObject;
class vtkSMProxy;
class qBMPanel;
class QTimer;

class pqBMDockWindow : public QDockWidget {
  Q_OBJECT
  using Superclass = QDockWidget;

public:
  /// Created by the plugin's dock window interface with the main window as parent.
  explicit pqBMDockWindow(QWidget* parent = nullptr);
  ~pqBMDockWindow() override;

  /// The hosted module panel.
  qBMPanel* panel() const { return this->Panel; }

protected:
  /// While a mouse-proxy session runs, the wheel over the active 3D view steps the proxy's depth
  /// (qBMSessionWidget::stepToolDepth) instead of zooming.
  bool eventFilter(QObject* watched, QEvent* event) override;

private Q_SLOTS:
  /// Creates a "BM Tool" source (vtkBMToolSource) with the given ToolType, Resolution and the tool
  /// section's edited parameters on the active server, applies it and shows it in the active
  /// view, if there is one.
  void addTool(int toolType, int resolution);
  /// Creates a "BM Session" source (vtkBMSessionSource) with the panel's choices (scene,
  /// resolutions, device, force model, tool, bone file, volume, a Touch's force scale), starts it
  /// (the panel shows a busy indicator while the bone is built) and shows the cut bone and the tool
  /// in the active view in their own colours, the camera framing the bone. The previous session, if
  /// any, is stopped and removed with its outputs. ParaView's live-source behaviour re-executes it
  /// as it cuts; pollSession() reads its numbers and, with the built-in server, its history into
  /// the panel
  /// (~30 Hz). On the CT bone, the CT is previewed with the panel's current settings first and
  /// an import error refuses the start.
  void startSession(const QString& scene, int voxmapResolution, int shellResolution,
                    int deviceType);
  void pauseSession(bool paused);
  void stopSession();
  void setToolDepth(double depthMm);
  void pollSession();
  /// Saves the session's cut bone to `path` through the SaveBone property (atomic in the logic)
  /// and reports the result in the panel.
  void saveBone(const QString& path);
  /// Turns the session's Volume output on or off and shows it with volume rendering in place of
  /// the bone's surface (which would hide it), or the surface again.
  void setVolumeRendering(bool on);
  /// Creates (once) or updates a "BM CT Bone" source (vtkBMCTBoneSource) with the panel's CT
  /// settings (the include seed, exclude points and oriented box too; malformed exclude points are
  /// refused naming the point; Ctrl+Shift+E / Ctrl+Shift+I over the 3D view pick them on the shown
  /// bone), shows its bone as a surface (the fraction's 0.5 contour) with the camera framing it,
  /// and reports the preview (bone voxels, volume, bounds, suggested entry, or the import error)
  /// in the panel. With no CT file named, an image open in the pipeline and selected (a reader's
  /// output) is the CT.
  void previewCT();
  /// The Planning section's settings onto a "BM Glenoid Plan" filter (created once) on the
  /// selected image source (a voxmap, a BM CT Bone), else the CT section's preview; its result,
  /// or why it failed, back into the section; its landmarks, rim and axis shown in the active
  /// view (pqBMDockPlanning.cxx).
  void planGlenoid();
  /// Runs step `step` of the plan (0 guide pin, 1 reaming) as a session on the step's scene (the
  /// step's tool, the CT's bone; the reaming on the bone the last session left, saved first).
  void runPlanStep(int step);
  /// Clicks in the 3D view place the glenoid while the Planning section's placement mode is on
  /// (its Click the face / Click the rim): a click (press and release within a few pixels, not a
  /// drag, which still turns the camera) on the shown bone sends the surface point under it to
  /// the section (qBMPlanWidget::addPlacedPoint).
  void setPlacementMode(int mode);
  /// The camera as the plan's pictures (bmPlanGlyphs.h PlanView): down the planned axis.
  void viewPlan();
  /// A slice of the CT (the image open in the pipeline, else the bone planned on) through the
  /// plan: 0 axial at the glenoid centre, 1 along the planned axis and the superior direction;
  /// one slice at a time, the camera square to it (pqBMDockPlanning.cxx).
  void showPlanSlice(int kind);
  /// Writes the plan's files and report into the section's report folder (the filter's
  /// WriteReport: as bmsim plan writes them) and says what was written, or why not.
  void writePlanReport();
  /// Writes the result of the plan's steps as they were run (the guide-pin session's bone at its
  /// start, the reaming session's bone now, both sessions' figures) into the section's report
  /// folder (the filter's WriteResult), or says why not (no reaming of this plan run yet).
  void writePlanResult();
  /// A landmark's handle was dragged in the 3D view (the plan filter's GlenoidCentre, Trigonum
  /// or InferiorAngle property changed outside planGlenoid): the section takes the point, uses
  /// it, and plans again (debounced while dragging).
  void syncDraggedLandmarks();

  /// Whether `source`'s first output is image data.
  static bool HoldsImage(pqPipelineSource* source);
  /// Whether it is a bone-fraction image the plan can read (a BM CT Bone, a voxmap opened: the
  /// BoneFraction array, or one scalar array within [0, 1]); a CT as read is not one (its values
  /// are HU or a window's 0-255, and its slices are seldom isotropic).
  static bool HoldsBoneFraction(pqPipelineSource* source);

private:
  Q_DISABLE_COPY(pqBMDockWindow);
  /// Stops and deletes the session source, its representations with it.
  void removeSession();
  /// The world point (mm) of the surface under the mouse in the active render view; false when
  /// the mouse is not over the view or over no surface.
  bool pickPoint(double world[3]) const;
  /// The same at `local` (the view widget's coordinates, pixels from its top left).
  bool pickPointAt(const QPoint& local, double world[3]) const;
  /// A mouse event on the view while placing the glenoid; true when it was a placing click.
  bool placementEvent(QEvent* event);
  /// Sets the plan filter's properties (`set`, as the dock: not a handle drag), runs its
  /// `command` (WriteReport, WriteResult) and shows what it wrote, or `refusal` with why not.
  void invokePlanWriter(const char* command, const QString& refusal,
                        const std::function<void(vtkSMProxy*)>& set);
  /// Shows the plan filter's glyphs in their own colours (the Colors array, not mapped).
  void showPlanGlyphs();
  /// The plan filter's property observer: a landmark changed while planGlenoid was not setting
  /// it (a handle dragged) starts HandleSync.
  void onPlanPropertyModified(vtkObject* caller, unsigned long event, void* name);
  qBMPanel* Panel;
  /// The view widget whose wheel steps the mouse proxy's depth (null: none).
  QPointer<QWidget> WheelView;
  QPointer<pqPipelineSource> Session;
  /// The session whose bone is being built (startSession waits for it; Stop cancels it).
  QPointer<pqPipelineSource> Starting;
  QPointer<pqPipelineSource> CTBone;
  QPointer<pqPipelineSource> CTSurface;       ///< the preview's bone surface: a Contour of CTBone
  QPointer<pqPipelineSource> CTImage;         ///< the open image BM CT Bone reads (null: its file)
  QPointer<pqPipelineSource> GlenoidPlan;     ///< the Planning section's BM Glenoid Plan filter
  QPointer<pqPipelineSource> PlanInput;       ///< the image it plans on
  QPointer<pqPipelineSource> PinStepSession;  ///< the session running the plan's guide-pin step
  QPointer<pqPipelineSource> PlanSlice;       ///< the slice through the plan (showPlanSlice)
  QPointer<pqPipelineSource> ReamStepSession; ///< the session running the plan's reaming step
  bool KeepInitialBoneNext = false; ///< the next session keeps its starting bone (pin step)
  bool StepSceneNext = false;       ///< the next session is a plan step's: its scene's own trial
  QString PlanBeforeBone;           ///< the pin step's starting bone, saved when reaming starts
  QString PinStepFigures;           ///< the pin step's figures (JSON), taken then
  QPointer<QWidget> PlaceView;      ///< the view widget clicks place the glenoid in
  QVector<QPointer<QObject>> PlaceTargets; ///< it, its render widget and OpenGL window
  QPoint PlacePress;                       ///< where the left button went down on it
  bool PlacePressed = false;
  bool SettingPlan = false;       ///< planGlenoid is setting the filter's properties
  unsigned long PlanObserver = 0; ///< the plan filter's property observer (handle drags)
  QTimer* HandleSync = nullptr;   ///< debounces handle drags into one plan
  bool PlanViewSet = false;       ///< the camera was put on the first plan
  QTimer* Poll;
  /// The bone last saved (Save bone, or the plan's pin step); the file keeps the trial it was cut
  /// on (vtkBMSessionSource::BoneFileTrial).
  QString SavedBone;
  /// Session frame the charts show, and the time since they were drawn.
  vtkIdType ChartedFrame = -1;
  QElapsedTimer ChartClock;
  bool ForceCharts = false; ///< draw the charts at the next poll whatever the time (Stop)
};
