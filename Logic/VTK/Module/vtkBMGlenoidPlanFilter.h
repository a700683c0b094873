// vtkBMGlenoidPlanFilter.h - glenoid planning in the plugin (Docs/Planning.md, Docs/Plugin.md
// "Planning"): a filter whose input is a bone-fraction image (the BM CT Bone output, a voxmap
// file bmsim import wrote, any vtkImageData holding 0..1 bone fractions) on which it runs the
// planning logic of `bmsim plan`: bm::SegmentedBone -> bm::DetectLandmarks -> bm::MeasureGlenoid
// -> bm::MakeGlenoidPlan.
//
// Input: vtkImageData, axis-aligned, isotropic spacing (mm); the point array "BoneFraction" when
// present, else the active point scalars (first component: a voxmap file's bone fraction). The
// glenoid is found where the scapula faces the humeral head, so the image must hold both bones
// (bmsim import --keep-all) unless the glenoid centre is given.
//
// Landmarks: each of the glenoid centre, the trigonum and the inferior angle is detected, or,
// with its Use... flag on, the given point (world mm) is used instead (what dragging its handle in
// the 3D view sets). A given glenoid centre keeps the detected face normal (or the given one,
// UseFaceNormal; with neither, the face's normal around it) and re-fits the rim around the given
// centre. Placed in the 3D view when detection fails (the dock's Place modes): a point clicked on
// the face (UseFacePoint: the glenoid traced around it as detection would), or three or more
// points clicked on the rim (RimPoints: their plane), bm::LandmarkOverrides.
//
// Output (vtkPolyData, world mm): the plan's glyphs as the report's pictures draw them
// (bmPlanGlyphs.h): the planned axis, the face normal, the reamer's outline on the planned face
// plane, the rim and the landmarks, each labelled, in its colour (point array "Colors", RGB; cell
// array "Part", bm::PlanGlyphPart). The plan's camera (down the axis, tilted 30 deg) in
// GetPlanCamera().
//
// Report: WriteReport() writes the plan's files into ReportDirectory as bmsim plan writes them
// (bmPlanFiles.h: plan.json, the step scenes, plan_report.md/.html/.json).
//
// Caching: the segmentation is redone only when the input changes; the detection of the joint
// (the expensive part) once per input; moving the trigonum or inferior angle, or changing the
// targets, re-runs only the measurements and the plan.
//
// Failure: when no glenoid is found (a CT without a shoulder, one bone only) the output is empty
// and GetLastError() says what was not found and how to place the glenoid (no error message, not
// a failed request: it is an answer the dock shows); a bad setting fails the request.
#pragma once

#include "BMVTKLogicModule.h" // for the export macro
#include "vtkPolyDataAlgorithm.h"

class BMVTKLOGIC_EXPORT vtkBMGlenoidPlanFilter : public vtkPolyDataAlgorithm {
public:
  static vtkBMGlenoidPlanFilter* New();
  vtkTypeMacro(vtkBMGlenoidPlanFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Landmark overrides, world mm (LPS), each used only with its Use... flag on (default off,
  /// (0, 0, 0)): the glenoid centre (on the articular face), the trigonum (the medial end of the
  /// scapular spine) and the inferior angle of the scapula.
  vtkSetMacro(UseGlenoidCentre, bool);
  vtkGetMacro(UseGlenoidCentre, bool);
  vtkBooleanMacro(UseGlenoidCentre, bool);
  vtkSetVector3Macro(GlenoidCentre, double);
  vtkGetVector3Macro(GlenoidCentre, double);
  /// The face normal (unit after normalising, pointing out of the joint; with UseFaceNormal,
  /// default off, (1, 0, 0)): with a given glenoid centre it skips the joint search, so a bone
  /// without a humeral head can be planned.
  vtkSetMacro(UseFaceNormal, bool);
  vtkGetMacro(UseFaceNormal, bool);
  vtkBooleanMacro(UseFaceNormal, bool);
  vtkSetVector3Macro(FaceNormal, double);
  vtkGetVector3Macro(FaceNormal, double);
  vtkSetMacro(UseTrigonum, bool);
  vtkGetMacro(UseTrigonum, bool);
  vtkBooleanMacro(UseTrigonum, bool);
  vtkSetVector3Macro(Trigonum, double);
  vtkGetVector3Macro(Trigonum, double);
  vtkSetMacro(UseInferiorAngle, bool);
  vtkGetMacro(UseInferiorAngle, bool);
  vtkBooleanMacro(UseInferiorAngle, bool);
  vtkSetVector3Macro(InferiorAngle, double);
  vtkGetVector3Macro(InferiorAngle, double);
  /// A point clicked on the glenoid face (world mm; used with UseFacePoint, default off, and no
  /// glenoid centre given): the glenoid whose joint lies within 15 mm of it, else the face
  /// traced around it (bm::LandmarkOverrides::facePoint).
  vtkSetMacro(UseFacePoint, bool);
  vtkGetMacro(UseFacePoint, bool);
  vtkBooleanMacro(UseFacePoint, bool);
  vtkSetVector3Macro(FacePoint, double);
  vtkGetVector3Macro(FacePoint, double);
  /// Points clicked on the glenoid's rim (world mm; default none): with three or more, and no
  /// glenoid centre, face normal or face point given, the glenoid's centre and normal are their
  /// plane's (the normal turned out of the bone).
  void AddRimPoint(double x, double y, double z);
  void RemoveAllRimPoints();
  int GetNumberOfRimPoints() const;
  ///@}
  ///@{
  /// Plan settings (bm::PlanOptions): target version and inclination of the reaming axis, deg
  /// (default 0 and 0, within (-45, 45)); reaming depth below the glenoid centre, mm (default 2);
  /// reamer diameter, mm (default 36.5, the built-in reamer); guide-pin hole radius, mm (default
  /// 3.2, above the nipple's 3) and depth below the centre, mm (default 0: ream depth + nipple
  /// 6 mm + 2 mm). Out-of-range values fail the request naming the setting.
  vtkSetMacro(TargetVersion, double);
  vtkGetMacro(TargetVersion, double);
  vtkSetMacro(TargetInclination, double);
  vtkGetMacro(TargetInclination, double);
  vtkSetMacro(ReamDepth, double);
  vtkGetMacro(ReamDepth, double);
  vtkSetMacro(ReamerDiameter, double);
  vtkGetMacro(ReamerDiameter, double);
  vtkSetMacro(PinRadius, double);
  vtkGetMacro(PinRadius, double);
  vtkSetMacro(PinDepth, double);
  vtkGetMacro(PinDepth, double);
  ///@}
  ///@{
  /// The CT the plan scene's bone is imported from (a DICOM folder or volume file; the plan
  /// scene's bone is the glenoid's bone in a box around the centre,
  /// bm::GlenoidPlan::CtBoneJsonWithSettings). Empty (default): no plan scene (GetPlanScene() is
  /// "").
  vtkSetStringMacro(CTFileName);
  vtkGetStringMacro(CTFileName);
  /// How that CT is read, as the BM CT Bone source that made the input gives it (its
  /// GetBoneSpecification(): the CT's path under "ct" with its intensity mode, threshold,
  /// series and exclude points, bmImport.h ImportOptionsFromJson keys). When set it replaces
  /// CTFileName, so the step scenes read the CT with the same settings as the plan's bone
  /// (bm::GlenoidPlan::CtBoneJsonWithSettings). Empty (default): CTFileName read with default
  /// settings.
  vtkSetStringMacro(CTBoneSpecification);
  vtkGetStringMacro(CTBoneSpecification);
  ///@}

  ///@{
  /// Results of the last execution (zero when it failed). Angles in deg: Friedman's 2D version
  /// and the 3D version (negative = retroversion), inclination (positive = superior), the
  /// correction from the face normal to the planned axis; lengths in mm: glenoid height, width,
  /// the face's radius of curvature.
  vtkGetMacro(FriedmanVersion, double);
  vtkGetMacro(Version3D, double);
  vtkGetMacro(Inclination, double);
  vtkGetMacro(GlenoidHeight, double);
  vtkGetMacro(GlenoidWidth, double);
  vtkGetMacro(FaceRadius, double);
  vtkGetMacro(Correction, double);
  /// Whether the reamer fits the glenoid (no overhang); 0 also when the plan failed.
  vtkGetMacro(ReamerFits, int);
  /// 1 when the measurements are implausible for a glenoid (version or inclination beyond
  /// +-30 deg, correction beyond 15 deg: bm::GlenoidPlan::implausible; the warnings say which).
  vtkGetMacro(Implausible, int);
  /// The landmarks used (detected or given), world mm.
  vtkGetVector3Macro(UsedGlenoidCentre, double);
  vtkGetVector3Macro(UsedTrigonum, double);
  vtkGetVector3Macro(UsedInferiorAngle, double);
  /// The face normal used (detected or given; unit, out of the joint).
  vtkGetVector3Macro(UsedFaceNormal, double);
  /// Friedman's glenoid line on the axial slice through the glenoid centre: its anterior and
  /// posterior ends on the rim (x, y, z, x, y, z; mm). The scapular axis of Friedman's version
  /// runs from the trigonum to its midpoint.
  vtkGetVector6Macro(GlenoidLine, double);
  /// The planned entry (the glenoid centre, mm) and axis (unit, out of the bone).
  vtkGetVector3Macro(PlanEntry, double);
  vtkGetVector3Macro(PlanAxis, double);
  /// The plan's warnings, one a line ("" none).
  const char* GetWarnings();
  /// Why the last execution failed ("" when it succeeded), e.g. "no glenoid found: ... place
  /// landmarks".
  const char* GetLastError();
  /// The plan as a scene with two steps (guide pin, ream) on the CT's bone (JSON,
  /// bm::GlenoidPlan::SceneJson, with "planning"."landmarks" and "measurements" as bmsim plan
  /// writes them); "" without CTFileName or CTBoneSpecification, or when the plan failed.
  const char* GetPlanScene();
  /// Each step alone as a plain single-step scene on the CT's bone (bm::GlenoidPlan::
  /// StepSceneJson; a session runs it: vtkBMSessionSource Scene): the guide-pin hole, and the
  /// reaming (on the bone the pin step left: vtkBMSessionSource BoneFile). "" as GetPlanScene().
  const char* GetPinStepScene();
  const char* GetReamStepScene();
  /// The plan's camera (bmPlanGlyphs.h PlanView): focal point (the entry, mm), the unit direction
  /// from it to the eye, the view-up, and the half height in mm the view should show (10 values;
  /// zero when the plan failed).
  vtkGetVectorMacro(PlanCamera, double, 10);
  /// How many times the joint detection ran (for tests of the caching).
  vtkGetMacro(DetectionCount, int);
  ///@}

  ///@{
  /// The folder WriteReport() writes into (created when missing; default none).
  vtkSetStringMacro(ReportDirectory);
  vtkGetStringMacro(ReportDirectory);
  /// Writes the last plan's files into ReportDirectory as bmsim plan does (bmPlanFiles.h): with a
  /// plan, plan.json and the step scenes (when the CT is known) and plan_report.md/.html/.json;
  /// after a failed plan, the report of why. Returns false, with GetReportError() saying why,
  /// when there is no folder, no plan was made or a file cannot be written (nothing is then
  /// written).
  bool WriteReport();
  /// Why the last WriteReport() or WriteResult() failed ("" when it wrote), and what it wrote
  /// (one name a line).
  const char* GetReportError();
  const char* GetReportFiles();
  /// The plan's steps as they were run (in the viewer: the guide-pin and reaming sessions): the
  /// bone before the first step and after the last (voxmap files on one grid, as the sessions'
  /// SaveInitialBone and SaveBone write them) and each step's figures (a JSON array of {step,
  /// name, tool, summary: {reached_depth_mm, removed_volume_mm3, ...}}).
  vtkSetStringMacro(ResultBeforeBone);
  vtkGetStringMacro(ResultBeforeBone);
  vtkSetStringMacro(ResultAfterBone);
  vtkGetStringMacro(ResultAfterBone);
  vtkSetStringMacro(ResultSteps);
  vtkGetStringMacro(ResultSteps);
  /// Writes the plan's result into ReportDirectory as bmsim run writes a plan's (bmPlanResult.h):
  /// the outcome of the reaming on the bone (the last plan's reamer, to the reaming step's reached
  /// depth), the glenoid's pictures before and after with the plan drawn, summary.json and
  /// plan_result.md/.html. Returns false, with GetReportError() saying why, when there is no
  /// plan with steps, no folder, a bone file is missing or unreadable, the two bones are not on
  /// one grid, or a file cannot be written.
  bool WriteResult();
  /// With WriteResult(), also the result as DICOM beside the plan's CT (bmPlanDicomResults.h:
  /// dicom/reamed-bone.seg.dcm and dicom/plan.sr.dcm in ReportDirectory), as bmsim run --dicom
  /// writes it; the CT must be a DICOM series, checked before anything is written (default off).
  vtkSetMacro(ResultAsDicom, bool);
  vtkGetMacro(ResultAsDicom, bool);
  vtkBooleanMacro(ResultAsDicom, bool);
  ///@}

protected:
  vtkBMGlenoidPlanFilter();
  ~vtkBMGlenoidPlanFilter() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  bool UseGlenoidCentre = false;
  double GlenoidCentre[3] = {0, 0, 0};
  bool UseFaceNormal = false;
  double FaceNormal[3] = {1, 0, 0};
  bool UseTrigonum = false;
  double Trigonum[3] = {0, 0, 0};
  bool UseInferiorAngle = false;
  double InferiorAngle[3] = {0, 0, 0};
  bool UseFacePoint = false;
  double FacePoint[3] = {0, 0, 0};
  double TargetVersion = 0;
  double TargetInclination = 0;
  double ReamDepth = 2.0;
  double ReamerDiameter = 36.5;
  double PinRadius = 3.2;
  double PinDepth = 0;
  char* CTFileName = nullptr;
  char* CTBoneSpecification = nullptr;
  char* ReportDirectory = nullptr;
  bool ResultAsDicom = false;
  char* ResultBeforeBone = nullptr;
  char* ResultAfterBone = nullptr;
  char* ResultSteps = nullptr;

  double FriedmanVersion = 0, Version3D = 0, Inclination = 0;
  double GlenoidHeight = 0, GlenoidWidth = 0, FaceRadius = 0, Correction = 0;
  int ReamerFits = 0;
  int Implausible = 0;
  double UsedGlenoidCentre[3] = {0, 0, 0};
  double UsedTrigonum[3] = {0, 0, 0};
  double UsedInferiorAngle[3] = {0, 0, 0};
  double UsedFaceNormal[3] = {0, 0, 0};
  double GlenoidLine[6] = {0, 0, 0, 0, 0, 0};
  double PlanEntry[3] = {0, 0, 0};
  double PlanAxis[3] = {0, 0, 0};
  double PlanCamera[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  int DetectionCount = 0;

private:
  vtkBMGlenoidPlanFilter(const vtkBMGlenoidPlanFilter&) = delete;
  void operator=(const vtkBMGlenoidPlanFilter&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};
