// bmsim import - CT (DICOM folder, NRRD/MHA/NIfTI file or InVesalius project) -> voxmap file.
#if __has_include("bmImport.h") // built only with CT import (BM_WITH_ITK)
#include "bmsimArgs.h"
#include "bmsimCTOptions.h"
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
      .Int("resolution", 8, 8192, "cells along the ROI's longest axis (default 256)");
  AddCTOptions(p, CTOptionsFor::Import);
  p.Flag("q,quiet", "no progress bar");
}

#ifdef BM_WITH_VTK
/// A VTK image file (.vti, legacy .vtk) read by VTK and imported as the BM CT Bone source
/// imports an image (bmVTKImageVolume.h): the volume goes through a MetaImage copy beside the
/// output (removed in every case) into the same import as any CT file (bmsimCTOptions.h).
static bm::ImportResult ImportVTKImageFile(const std::string& input, const std::string& output,
                                           const bm::ImportOptions& opt,
                                           const bm::Progress& progress) {
  namespace fs = std::filesystem;
  bm::CheckVoxmapOutputPath(output);
  std::error_code ec;
  if (fs::equivalent(input, output, ec))
    throw std::runtime_error("--out " + output + " is the input: choose another file");
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
  bool copied = false;
  bm::ImportResult r = ImportCT(input, opt, copy.string(), copied, progress.Range(0, 0.9));
  bm::SaveVoxmap(r.voxmap, output, progress.Range(0.9, 1),
                 {{"bm_intensity_mapping", r.intensity.Key()},
                  {"bm_intensity", r.intensity.Describe()},
                  {"bm_material_calibrated", r.intensity.materialCalibrated ? "true" : "false"}});
  return r;
}
#endif

static int ImportCommand(const ParsedArgs& p) {
  bm::ImportOptions opt = CTOptionsFromArgs(p, CTOptionsFor::Import);
  if (const auto n = p.GetInt("resolution", 8, 8192))
    opt.resolution = int(*n);
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
