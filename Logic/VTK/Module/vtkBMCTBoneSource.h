// vtkBMCTBoneSource.h - a CT's bone as the machining voxmap sees it: the CT step of the plugin,
// a filter with an OPTIONAL vtkImageData input. The CT is
//  - the input image when one is connected (any CT ParaView opened: DICOM, NRRD, MHA, NIfTI,
//    .vti/.vtk, ...; its active point scalars, first component, as HU; origin, spacing and
//    direction in world mm), else
//  - FileName: a DICOM folder, a .nrrd / .mha / .nii / .nii.gz / .dcm file as Logic/IO reads
//    them, or a VTK image file (.vti, or legacy .vtk structured points) read by VTK's readers;
// segmented at a threshold (HU) inside a region of interest (mm), resampled to a voxmap.
//
// The same import `bmsim import` and CT scenes run (Logic/IO bmImport: read, crop to the ROI,
// segment, separate, fill cavities, resample; Docs/Segmentation.md), so what the preview shows
// is what a session on this bone machines. Output: vtkImageData with point data BoneFraction
// (0..1, the voxmap's fill fraction at the voxel centres, world mm), for an outline, a slice or
// volume rendering in ParaView. Information: the bone's voxel count and volume, its bounds, an
// entry point suggested on the bone's surface along an axis, and the bone specification (JSON)
// a vtkBMSessionSource machines (SetBoneCT(); an input image or a VTK file is first written as a
// MetaImage CT in the temporary folder so the session can import it at its own resolution).
//
// The import runs in RequestInformation (so that the image's extent is known before data is
// requested; an input is brought up to date first), once per change of the settings or the
// input, reporting through UpdateProgress (ParaView's progress bar). Bad input (missing file,
// no bone above the threshold, an inverted ROI) fails the execution with the importer's message
// in GetLastError(); the output is then empty.
//
// Units: mm, HU, mm^3.
#pragma once

#include "BMVTKLogicModule.h" // for the export macro
#include "vtkImageAlgorithm.h"

#include <string> // for ImportOptionsJson
#include <vector> // for ExcludePoints

class BMVTKLOGIC_EXPORT vtkBMCTBoneSource : public vtkImageAlgorithm {
public:
  static vtkBMCTBoneSource* New();
  vtkTypeMacro(vtkBMCTBoneSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The CT when no input image is connected: a DICOM folder or a volume file (.nrrd, .mha,
  /// .nii, .nii.gz, .dcm, .vti, .vtk). Default none.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}
  ///@{
  /// Bone threshold, HU: voxels at or above are bone. Default 200 HU.
  vtkSetMacro(ThresholdHU, double);
  vtkGetMacro(ThresholdHU, double);
  ///@}
  ///@{
  /// How the CT's values are read (Docs/CTImport.md, "Intensities"):
  ///  - IntensityFromFile (default): Hounsfield units as the file or image gives them; values
  ///    that are clearly not HU (a windowed 8-bit image, every value a whole number in 0..255, no
  ///    rescale) are refused with a message naming the two other modes;
  ///  - IntensityRaw: the values as stored; bone = values at or above RawThreshold (the file's
  ///    units, default 128); ThresholdHU is not used and the material scale is uniform (1, not
  ///    calibrated);
  ///  - IntensityMapped: HU = HUMapping[0] x value + HUMapping[1] (slope, intercept; default 1,
  ///    -1024), then ThresholdHU applies.
  enum IntensityModes { IntensityFromFile = 0, IntensityRaw = 1, IntensityMapped = 2 };
  vtkSetClampMacro(IntensityMode, int, IntensityFromFile, IntensityMapped);
  vtkGetMacro(IntensityMode, int);
  vtkSetMacro(RawThreshold, double);
  vtkGetMacro(RawThreshold, double);
  vtkSetVector2Macro(HUMapping, double);
  vtkGetVector2Macro(HUMapping, double);
  ///@}
  ///@{
  /// Region of interest (x0, y0, z0, x1, y1, z1: the one ROI order of the CLI and scenes), world
  /// mm. All zeros (the default) means none: the bounding box of the segmented bone. An inverted
  /// or empty box (any x1 <= x0, ...) is an error.
  vtkSetVector6Macro(ROI, double);
  vtkGetVector6Macro(ROI, double);
  ///@}
  ///@{
  /// Include seed (world mm): keep the bone at this point (with UseSeed; default off, (0, 0, 0)):
  /// the point the 3D view's handle widget places. Off: the largest bone.
  vtkSetMacro(UseSeed, bool);
  vtkGetMacro(UseSeed, bool);
  vtkBooleanMacro(UseSeed, bool);
  vtkSetVector3Macro(Seed, double);
  vtkGetVector3Macro(Seed, double);
  ///@}
  ///@{
  /// Keep every bone component, not only the largest (or the seeded one): a shoulder's scapula
  /// and humeral head together, for planning (vtkBMGlenoidPlanFilter finds the joint between
  /// them). Default off (one bone: the bone a session machines). `bmsim import --keep-all`.
  vtkSetMacro(KeepAllBones, bool);
  vtkGetMacro(KeepAllBones, bool);
  vtkBooleanMacro(KeepAllBones, bool);
  ///@}
  ///@{
  /// Exclude seeds (world mm): bones to drop, split from the kept bone across a joint space
  /// (Docs/Segmentation.md). A point off all bone is ignored (the import warns). Default none.
  void AddExcludePoint(double x, double y, double z);
  void RemoveAllExcludePoints();
  int GetNumberOfExcludePoints() const;
  ///@}
  ///@{
  /// Oriented box region (with UseBox; default off): centre (mm), half sizes (mm, default 50)
  /// and rotation (degrees about world x, y and z, applied y first, then x, then z: the order of
  /// ParaView's box widget, which the plugin shows for it; default 0) (bmBoxROI.h).
  vtkSetMacro(UseBox, bool);
  vtkGetMacro(UseBox, bool);
  vtkBooleanMacro(UseBox, bool);
  vtkSetVector3Macro(BoxCentre, double);
  vtkGetVector3Macro(BoxCentre, double);
  vtkSetVector3Macro(BoxHalfSizes, double);
  vtkGetVector3Macro(BoxHalfSizes, double);
  vtkSetVector3Macro(BoxRotation, double);
  vtkGetVector3Macro(BoxRotation, double);
  ///@}
  ///@{
  /// The reference box of ParaView's box widget (pqBoxPropertyWidget, "InteractiveBox"): the box
  /// cut is the reference box scaled by BoxHalfSizes, rotated by BoxRotation and moved by
  /// BoxCentre, so that what the 3D widget shows is what is kept. With the default reference
  /// [-1, 1]^3 (BoxUseReferenceBounds on) BoxCentre is the centre and BoxHalfSizes the half sizes;
  /// with BoxUseReferenceBounds off the reference is the unit cube [0, 1]^3 (BoxCentre is then a
  /// corner). Bounds: x0, x1, y0, y1, z0, z1 (unitless; an empty reference is an error).
  vtkSetMacro(BoxUseReferenceBounds, bool);
  vtkGetMacro(BoxUseReferenceBounds, bool);
  vtkSetVector6Macro(BoxReferenceBounds, double);
  vtkGetVector6Macro(BoxReferenceBounds, double);
  ///@}
  ///@{
  /// Voxmap cells along the region's longest side. Default 96 (a preview; a session resamples at
  /// its own resolution), clamped to [8, 1024].
  vtkSetClampMacro(Resolution, int, 8, 1024);
  vtkGetMacro(Resolution, int);
  ///@}
  ///@{
  /// Axis the tool comes in along (world, from the bone out toward the shank; normalized when
  /// used). Default (0, 0, 1). Used by GetSuggestedEntry().
  vtkSetVector3Macro(Axis, double);
  vtkGetVector3Macro(Axis, double);
  ///@}

  ///@{
  /// Results of the last execution: voxels holding bone, bone volume (mm^3), the voxmap's
  /// bounds (x0, x1, y0, y1, z0, z1, mm), and the entry point suggested for Axis (mm): where the
  /// line along Axis through the bone's bounds centre first meets a voxel at least half bone,
  /// coming from outside (the bounds centre itself when the line misses the bone).
  vtkGetMacro(BoneVoxels, vtkIdType);
  vtkGetMacro(BoneVolumeMm3, double);
  vtkGetVector6Macro(BoneBounds, double);
  vtkGetVector3Macro(SuggestedEntry, double);
  /// Why the last execution failed ("" when it succeeded).
  const char* GetLastError();
  /// The last import's summary, as `bmsim import` prints it: what was read, the intensity
  /// mapping used (HU, a given mapping or raw values) and whether the material scale is
  /// calibrated, the bone's volume at the CT's resolution and in the voxmap, warnings. "" when
  /// the last execution failed.
  const char* GetImportReport();
  /// The bone as a session machines it: {"ct": CT file (absolute; for an input image or a VTK
  /// file, the MetaImage copy written at the last import), "threshold": HU, "roi": [x0, y0, z0,
  /// x1, y1, z1]} (roi only when set; "rawThreshold" or "huMapping" with IntensityMode), the "ct" description of a scene's bone (bmImport.h
  /// ImportOptionsFromJson). "" without a CT.
  const char* GetBoneSpecification();
  ///@}

protected:
  vtkBMCTBoneSource();
  ~vtkBMCTBoneSource() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
                          vtkInformationVector* outputVector) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
                         vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  char* FileName = nullptr;
  double ThresholdHU = 200.0;
  int IntensityMode = IntensityFromFile;
  double RawThreshold = 128.0;
  double HUMapping[2] = {1.0, -1024.0};
  double ROI[6] = {0, 0, 0, 0, 0, 0};
  int Resolution = 96;
  double Axis[3] = {0, 0, 1};
  bool UseSeed = false;
  bool KeepAllBones = false;
  double Seed[3] = {0, 0, 0};
  std::vector<double> ExcludePoints; ///< x, y, z per point, mm
  bool UseBox = false;
  double BoxCentre[3] = {0, 0, 0};
  double BoxHalfSizes[3] = {50, 50, 50};
  double BoxRotation[3] = {0, 0, 0};
  bool BoxUseReferenceBounds = true;
  double BoxReferenceBounds[6] = {-1, 1, -1, 1, -1, 1};
  vtkIdType BoneVoxels = 0;
  double BoneVolumeMm3 = 0;
  double BoneBounds[6] = {0, 0, 0, 0, 0, 0};
  double SuggestedEntry[3] = {0, 0, 0};

private:
  /// The import options (JSON, bmImport.h ImportOptionsFromJson keys) of the current settings.
  /// Throws std::runtime_error on an empty box reference.
  std::string ImportOptionsJson() const;
  /// Imports the CT (`input` when not null, else FileName) with the current settings into the
  /// internals and fills the results (or the error).
  void Import(class vtkImageData* input);
  vtkBMCTBoneSource(const vtkBMCTBoneSource&) = delete;
  void operator=(const vtkBMCTBoneSource&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};
