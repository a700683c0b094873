// bmsim import - CT (DICOM folder, NRRD/MHA/NIfTI file or InVesalius project) -> voxmap file.
#if __has_include("bmImport.h") // built only with CT import (BM_WITH_ITK)
#include "bmsimArgs.h"
#include "bmsimCommand.h"

#include "bmAtomicFile.h"
#include "bmImport.h"
#include "bmVoxmapFile.h"
#ifdef BM_WITH_VTK
#include "bmVTKImageVolume.h"
#include "vtkImageData.h"
#endif

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <algorithm>
#include <memory>

namespace {

std::atomic<bool> gInterrupted{false};

} // namespace

namespace bm::cli {

/// Progress bar on the terminal (stderr), only when stderr is a terminal. Ctrl-C cancels.
ProgressFn TerminalProgress(bool quiet) {
  const bool tty = !quiet && isatty(2);
  auto lastPercent = std::make_shared<int>(-1);
  auto lastStage = std::make_shared<std::string>();
  return [tty, lastPercent, lastStage](double f, const std::string& stage) {
    if (gInterrupted.load())
      return false;
    if (!tty)
      return true;
    int pct = int(f * 100.0 + 0.5);
    if (pct == *lastPercent && stage == *lastStage)
      return true;
    *lastPercent = pct;
    *lastStage = stage;
    const int width = 30, filled = int(f * width + 0.5);
    std::fprintf(stderr, "\r[%.*s%*s] %3d%% %-40.40s", filled, "##############################",
                 width - filled, "", pct, stage.c_str());
    if (f >= 1.0 && stage.rfind("saving", 0) == 0)
      std::fprintf(stderr, "\n");
    std::fflush(stderr);
    return true;
  };
}

static void ImportCommandOptions(ParsedArgs& p) {
  p.Words("INPUT", "DICOM folder, .nrrd/.nhdr/.mha/.mhd/.nii/.nii.gz file, .vti/.vtk VTK image "
                   "(read by VTK) or .inv3 project")
      .Value("o,out", "FILE",
             "voxmap to write (.nrrd or .mha; written only when everything succeeded; required)")
      .Int("resolution", 8, 8192, "cells along the ROI's longest axis (default 256)")
      .Real("threshold", -1000, 4000, "HU", "bone threshold in Hounsfield units (default 200)")
      .Value("seed", "X,Y,Z", "world point (mm) on the bone to keep (default: the largest bone)")
      .Value("exclude", "X,Y,Z[;X,Y,Z...]",
             "world points (mm) on bones to drop: split from the kept bone across the joint "
             "space (a point off all bone is a warning)")
      .Value("roi", "X0,Y0,Z0,X1,Y1,Z1",
             "region of interest, world mm (default: the bone's bounding box; an inverted box "
             "is an error)")
      .Value("box", "CX,CY,CZ,HX,HY,HZ[,RX,RY,RZ]",
             "oriented box region: centre, half sizes (mm), rotation about x, y, z (degrees; "
             "applied y, then x, then z, as VTK and ParaView's box widget do)")
      .Value("series", "ID",
             "series to read when the folder holds several: the id listed (SeriesInstanceUID, "
             "or noUID-... for a series without one)")
      .Real("raw-threshold", -1e9, 1e9, "V",
            "values are not HU: use them as stored, bone = values >= V in the file's units "
            "(material scale uniform, not calibrated)")
      .Value("hu-mapping", "A,B",
             "values are not HU: HU = A x value + B (then --threshold is in HU)")
      .Flag("allow-outside-data", "accept a header's data file outside the header's folder")
      .Real("max-memory", 1, 1e9, "MB",
            "memory the import may use (default 75 % of the memory this process may use: physical, "
            "or its cgroup limit)")
      .Flag("keep-all", "keep every bone component, not only the largest")
      .Flag("no-fill-holes", "do not fill cavities inside the bone")
      .Flag("q,quiet", "no progress bar");
}

#ifdef BM_WITH_VTK
/// A VTK image file (.vti, legacy .vtk) read by VTK's readers and imported as the BM CT Bone
/// source imports an image (bmVTKImageVolume.h): the volume goes through a MetaImage copy beside
/// the output (removed in every case) into the same import as any CT file.
static bm::ImportResult ImportVTKImageFile(const std::string& input, const std::string& output,
                                           const bm::ImportOptions& opt,
                                           const bm::Progress& progress) {
  namespace fs = std::filesystem;
  bm::CheckVoxmapOutputPath(output);
  std::error_code ec;
  if (fs::equivalent(input, output, ec))
    throw std::runtime_error("--out " + output + " is the input: choose another file");
  const vtkSmartPointer<vtkImageData> image = bm::ReadVTKImageFile(input);
  bm::VTKImageVolume volume;
  bm::VolumeFromVTKImage(image, input, volume);
  // A temporary of bm::TemporarySibling's pattern: what a killed import leaves, the next run in
  // that folder removes (bm::RemoveStaleTemporaries).
  const fs::path copy =
      bm::TemporarySibling((fs::absolute(output).parent_path() / "bmsim-import-copy.mha").string());
  struct Remove {
    fs::path path;
    ~Remove() {
      std::error_code e;
      fs::remove(path, e);
    }
  } removeCopy{copy};
  bm::SaveCTVolume(volume.view, copy.string());
  bm::ImportResult r = bm::ImportToFile(copy.string(), output, opt, progress);
  r.source = input;
  r.format = fs::path(input).extension() == ".vti" ? "VTK XML image data, read by VTK"
                                                   : "VTK legacy structured points, read by VTK";
  return r;
}
#endif

static int ImportCommand(const ParsedArgs& p) {
  bm::ImportOptions opt;
  if (const auto n = p.GetInt("resolution", 8, 8192))
    opt.resolution = int(*n);
  if (const auto t = p.GetDouble("threshold", -1000, 4000))
    opt.segmentation.thresholdHU = float(*t);
  if (const auto s = p.GetDoubles("seed", 3))
    opt.segmentation.seedMm = std::array<double, 3>{(*s)[0], (*s)[1], (*s)[2]};
  if (const auto r = p.GetDoubles("roi", 6))
    opt.roiMm = bm::RoiFromCorners(*r, "--roi");
  if (const auto e = p.Get("exclude"))
    opt.segmentation.excludeSeedsMm = bm::ParsePointsMm(*e, "--exclude");
  if (const auto b = p.Get("box"))
    opt.segmentation.box = bm::OrientedBoxFromText(*b, "--box");
  if (const auto uid = p.Get("series"))
    opt.read.seriesUID = *uid;
  if (const auto v = p.GetDouble("raw-threshold", -1e9, 1e9)) {
    if (p.Has("threshold"))
      throw UsageError("--raw-threshold replaces --threshold (it is the threshold in the file's "
                       "units): give one of them");
    opt.read.intensity.rawThreshold = *v;
  }
  if (const auto m = p.GetDoubles("hu-mapping", 2)) {
    if (p.Has("raw-threshold"))
      throw UsageError("give either --raw-threshold or --hu-mapping, not both");
    if ((*m)[0] == 0)
      throw UsageError("--hu-mapping: the slope A must not be 0");
    opt.read.intensity.huMapping = std::array<double, 2>{(*m)[0], (*m)[1]};
  }
  opt.read.allowDataOutsideFolder = p.Has("allow-outside-data");
  if (const auto mb = p.GetDouble("max-memory", 1, 1e9))
    opt.read.maxMemoryBytes = uint64_t(*mb * 1048576.0);
  opt.segmentation.keepAllComponents = p.Has("keep-all");
  opt.segmentation.fillHoles = !p.Has("no-fill-holes");
  const bool quiet = p.Has("quiet");
  const auto& pos = p.Positional();
  if (pos.size() > 1)
    throw UsageError("more than one INPUT ('" + pos[0] + "', '" + pos[1] + "')");
  if (pos.empty())
    throw UsageError("no INPUT given");
  const std::string& input = pos[0];
  const std::string output = p.Get("out", "");
  if (output.empty())
    throw UsageError("--out VOXMAP.nrrd is required");
  std::signal(SIGINT, [](int) { gInterrupted = true; });
  bm::ImportResult r;
  try {
    const bm::Progress progress(TerminalProgress(quiet));
#ifdef BM_WITH_VTK
    if (bm::IsVTKImageFile(input))
      r = ImportVTKImageFile(input, output, opt, progress);
    else
#endif
      r = bm::ImportToFile(input, output, opt, progress);
  } catch (...) {
    if (!quiet && isatty(2))
      std::fprintf(stderr, "\n");
    throw;
  }
  std::cout << r.Report() << "wrote:       " << output << "\n";
  return 0;
}

BM_REGISTER_COMMAND(import,
                    "CT (DICOM folder or volume file) -> segmented bone voxmap (.nrrd/.mha)",
                    ImportCommandOptions, ImportCommand);

} // namespace bm::cli
#endif
