// bmsim import - CT (DICOM folder, NRRD/MHA/NIfTI file or InVesalius project) -> voxmap file.
#if __has_include("bmImport.h") // built only with CT import (BM_WITH_ITK)
#include "bmsimCommand.h"

#include "bmImport.h"
#include "bmVoxmapFile.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

namespace {

const char* kUsage =
    "usage: bmsim import INPUT --out VOXMAP.nrrd|.mha [options]\n"
    "  INPUT                 DICOM folder, .nrrd/.nhdr/.mha/.mhd/.nii/.nii.gz file or .inv3 "
    "project\n"
    "  --out FILE            voxmap to write (.nrrd or .mha; written only when everything "
    "succeeded)\n"
    "  --resolution N        cells along the ROI's longest axis (default 256)\n"
    "  --threshold HU        bone threshold in Hounsfield units (default 200)\n"
    "  --seed X,Y,Z          world point (mm) on the bone to keep (default: the largest bone)\n"
    "  --roi X0,Y0,Z0,X1,Y1,Z1  region of interest, world mm (default: the bone's bounding box)\n"
    "  --series UID          SeriesInstanceUID when the folder holds several series\n"
    "  --max-memory MB       memory the import may use (default 75 % of physical memory)\n"
    "  --keep-all            keep every bone component, not only the largest\n"
    "  --no-fill-holes       do not fill cavities inside the bone\n"
    "  --quiet               no progress bar\n";

std::atomic<bool> gInterrupted{false};

std::vector<double> ParseList(const std::string& opt, const std::string& s, size_t n) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string part;
  while (std::getline(ss, part, ',')) {
    try {
      size_t used = 0;
      v.push_back(std::stod(part, &used));
      if (used != part.size())
        throw std::invalid_argument(part);
    } catch (const std::exception&) {
      throw bm::cli::UsageError(opt + " expects " + std::to_string(n) +
                                " comma-separated numbers, got '" + s + "'");
    }
  }
  if (v.size() != n)
    throw bm::cli::UsageError(opt + " expects " + std::to_string(n) +
                              " comma-separated numbers, got '" + s + "'");
  return v;
}

double ParseNumber(const std::string& opt, const std::string& s) {
  try {
    size_t used = 0;
    double v = std::stod(s, &used);
    if (used == s.size())
      return v;
  } catch (const std::exception&) {
  }
  throw bm::cli::UsageError(opt + " expects a number, got '" + s + "'");
}

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

static int ImportCommand(const Args& args) {
  std::string input, output;
  bm::ImportOptions opt;
  bool quiet = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size())
        throw UsageError(a + " needs a value\n" + kUsage);
      return args[++i];
    };
    if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return 0;
    } else if (a == "--out" || a == "-o") {
      output = value();
    } else if (a == "--resolution") {
      double n = ParseNumber(a, value());
      if (n != double(int(n)) || n < 8 || n > 8192)
        throw UsageError("--resolution must be an integer 8 .. 8192");
      opt.resolution = int(n);
    } else if (a == "--threshold") {
      opt.segmentation.thresholdHU = float(ParseNumber(a, value()));
    } else if (a == "--seed") {
      auto s = ParseList(a, value(), 3);
      opt.segmentation.seedMm = std::array<double, 3>{s[0], s[1], s[2]};
    } else if (a == "--roi") {
      auto r = ParseList(a, value(), 6);
      bm::Box3 b;
      for (int k = 0; k < 3; ++k) {
        b.lo[k] = std::min(r[k], r[k + 3]);
        b.hi[k] = std::max(r[k], r[k + 3]);
      }
      opt.roiMm = b;
    } else if (a == "--series") {
      opt.read.seriesUID = value();
    } else if (a == "--max-memory") {
      double mb = ParseNumber(a, value());
      if (!(mb > 0))
        throw UsageError("--max-memory must be a positive number of MB");
      opt.read.maxMemoryBytes = uint64_t(mb * 1048576.0);
    } else if (a == "--keep-all") {
      opt.segmentation.keepAllComponents = true;
    } else if (a == "--no-fill-holes") {
      opt.segmentation.fillHoles = false;
    } else if (a == "--quiet" || a == "-q") {
      quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option " + a + "\n" + kUsage);
    } else if (input.empty()) {
      input = a;
    } else {
      throw UsageError("more than one INPUT ('" + input + "', '" + a + "')\n" + kUsage);
    }
  }
  if (input.empty())
    throw UsageError(std::string("no INPUT given\n") + kUsage);
  if (output.empty())
    throw UsageError(std::string("--out VOXMAP.nrrd is required\n") + kUsage);
  std::signal(SIGINT, [](int) { gInterrupted = true; });
  bm::ImportResult r;
  try {
    r = bm::ImportToFile(input, output, opt, bm::Progress(TerminalProgress(quiet)));
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
                    ImportCommand);

} // namespace bm::cli
#endif
