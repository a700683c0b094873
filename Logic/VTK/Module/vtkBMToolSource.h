// vtkBMToolSource.h - surface mesh of a rotating surgical tool, for display.
//
// Revolves the half-section outline of a bm::ToolModel (Logic/Core/bmToolModel.h) about the tool
// axis. The output is in the tool frame of bm::ToolModel: z along the axis from the tip toward the
// shank, origin on the axis at the foremost cutting point (a non-cutting guide such as the
// reamer's nipple reaches below z = 0); units are mm. The z bounds equal GetAxialRange(). Point
// data "Normals" (outward, split at edges sharper than 30 degrees); cell data "EdgeKind" (unsigned
// char, bm::EdgeKind: 0 = non- cutting surface, 1 = cutting lip, 2 = chisel edge), so the cutting
// part of the tool can be coloured. The mesh is the time-averaged (axisymmetric) tool: it does not
// show flutes.
//
// This class only displays: the haptic engine samples the same bm::ToolModel itself.
#pragma once

#include "BMVTKLogicModule.h" // for the export macro
#include "vtkPolyDataAlgorithm.h"

class BMVTKLOGIC_EXPORT vtkBMToolSource : public vtkPolyDataAlgorithm {
public:
  static vtkBMToolSource* New();
  vtkTypeMacro(vtkBMToolSource, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Tool kinds, matching the "type" of a tool specification (bm::MakeTool).
  enum ToolTypes { DRILL = 0, REAMER = 1, BURR = 2 };

  ///@{
  /// Kind of tool: DRILL (the reference twist drill, radius 1.25 mm), REAMER (the spherical
  /// glenoid reamer, diameter 36.5 mm) or BURR (spherical burr, radius 2 mm). Default DRILL.
  vtkSetClampMacro(ToolType, int, DRILL, BURR);
  vtkGetMacro(ToolType, int);
  void SetToolTypeToDrill() { this->SetToolType(DRILL); }
  void SetToolTypeToReamer() { this->SetToolType(REAMER); }
  void SetToolTypeToBurr() { this->SetToolType(BURR); }
  /// "drill", "reamer" or "burr".
  const char* GetToolTypeAsString() const;
  ///@}

  ///@{
  /// Tool parameters overriding the defaults of ToolType, as a JSON object in the keys of a tool
  /// specification (for example {"radius_mm": 2.0} for a 4 mm drill; units in the key names).
  /// Empty or null (the default) keeps the defaults. A "type" key here is ignored: ToolType rules.
  vtkSetStringMacro(Parameters);
  vtkGetStringMacro(Parameters);
  ///@}

  ///@{
  /// Number of facets around the axis. Default 64, clamped to [3, 1024]. A multiple of 4 puts
  /// vertices on the x and y axes, so the bounds equal the tool's outer radius exactly.
  vtkSetClampMacro(Resolution, int, 3, 1024);
  vtkGetMacro(Resolution, int);
  ///@}

  ///@{
  /// Longest segment of the sampled outline, mm. Default 0.25 mm, clamped to [0.001, 100].
  vtkSetClampMacro(MaxSegmentLength, double, 0.001, 100.0);
  vtkGetMacro(MaxSegmentLength, double);
  ///@}

  ///@{
  /// Description of the tool currently configured (ToolType + Parameters), without executing the
  /// pipeline. All return 0 (and ToolIsValid false) when the parameters are invalid; then
  /// GetToolError() says why. Radii and lengths in mm.
  bool GetToolIsValid();
  const char* GetToolError();
  double GetOuterRadius();
  int GetNumberOfLips();
  /// Axial extent [zMin, zMax] of the tool, mm, in the tool frame (the surface's z bounds).
  void GetAxialRange(double range[2]);
  /// The same, in an array owned by this object and overwritten by the next call.
  double* GetAxialRange() VTK_SIZEHINT(2);
  /// The configured tool's whole specification as a JSON object: "type" and every parameter
  /// with its value (defaults included; units in the key names, e.g. "radius_mm",
  /// "point_angle_deg"), as bm::MakeTool reads it. Empty when the parameters are invalid. The
  /// string is owned by this object and valid until the next call.
  const char* GetToolSpecification();
  ///@}

protected:
  vtkBMToolSource();
  ~vtkBMToolSource() override;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  int ToolType = DRILL;
  char* Parameters = nullptr;
  int Resolution = 64;
  double MaxSegmentLength = 0.25;
  double AxialRange[2] = {0.0, 0.0};

private:
  vtkBMToolSource(const vtkBMToolSource&) = delete;
  void operator=(const vtkBMToolSource&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};
