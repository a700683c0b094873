// bmsimCTOptions.h - how a CT is read and segmented, as `bmsim import` and `bmsim plan` take it:
// one set of options (threshold or raw threshold, HU mapping, seed, exclude points, region,
// oriented box, series, memory, holes), one parser, and the VTK image files (.vti, .vtk) read the
// same way by both commands.
#pragma once

#include "bmImport.h"
#include "bmsimArgs.h"

#include <string>

namespace bm::cli {

/// Which command the options are for: `plan` keeps every bone (the humeral head shows where the
/// glenoid is), so it has no --keep-all and its --seed names the scapula only for the step scenes.
enum class CTOptionsFor { Import, Plan };

/// Declare the options on `p`.
void AddCTOptions(ParsedArgs& p, CTOptionsFor command);

/// The import options the parsed arguments give (usage errors for contradictory ones: a raw
/// threshold with --threshold, a raw threshold with an HU mapping, a zero slope).
ImportOptions CTOptionsFromArgs(const ParsedArgs& p, CTOptionsFor command);

/// Import `input` into a voxmap in memory. A VTK image file (.vti, .vtk, where this build reads
/// them) is read by VTK and saved as a MetaImage at `vtkCopy` first (a path the caller removes
/// or keeps: a scene can read the copy, not the VTK file); other inputs are read directly and
/// `vtkCopy` is not written. Returns whether the copy was written in `copied`.
ImportResult ImportCT(const std::string& input, const ImportOptions& options,
                      const std::string& vtkCopy, bool& copied, const Progress& progress);

} // namespace bm::cli
