// bmTrialReport.h - the planning report of a feed trial (`bmsim run SCENE --out DIR`): what was
// cut, how hard it pushed, how fast the frames ran, and pictures of it.
//
// Writes into DIR (created if missing), each file atomically:
//   <cut>.vtp, <cut>.stl  the cut bone's surface (fill fraction 0.5, flying edges; world mm), where
//                         <cut> is "reamed" for a reamer, "drilled" for a drill, "cut" otherwise
//   <cut>.png             a rendering of the cut bone seen from outside along the trial axis, the
//                         surface the tool cut shaded blue
//   thrust.png, torque.png, frame_time.png, removed_volume.png   charts over time (VTK charts)
//   report.md, report.html  the report: removed volume (mm^3), depth (mm), forces, frame times,
//                         the pictures, the files
// forces.csv and summary.json come from FeedTrial::WriteOutputs (the report links them).
// Rendering needs an X display: bm::VirtualDisplay::Ensure() starts Xvfb when DISPLAY is unset.
#pragma once

#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "bmFeedTrial.h"
#include "bmMachiningSetup.h"
#include "bmSurfaceImage.h"

class vtkPolyData;

namespace bm {

struct TrialReportFiles {
  std::string markdown, html; ///< DIR/report.md, DIR/report.html
  std::string surfaceVtp, surfaceStl, image;
  std::vector<std::string> charts; ///< the chart PNGs
};

/// The cut bone's surface after the trial, with an RGB point array "Colors": blue where the
/// surface lies on the tool's swept envelope (the cut), ivory elsewhere. World mm.
vtkSmartPointer<vtkPolyData> CutBoneSurface(MachiningSetup& setup, const FeedTrial& trial);
/// The camera of the report's picture: from outside the bone along the trial axis (tilted 20
/// degrees so the cut's depth shows), centred on the entry point, framing the whole voxmap.
SurfaceView TrialView(MachiningSetup& setup, int sizePx = 800);
/// Writes the report and its files into `dir` (see above). Throws std::runtime_error on failure.
TrialReportFiles WriteTrialReport(const std::string& dir, MachiningSetup& setup,
                                  const FeedTrial& trial);

} // namespace bm
