// bmsim phantom - write a synthetic CT (glenoid or cortical block) as a real DICOM series.
#if __has_include("bmPhantom.h") // built only with CT import (BM_WITH_ITK)
#include "bmsimArgs.h"
#include "bmsimCommand.h"

#include "bmPhantom.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>

namespace {
const char* kUsage =
    "usage: bmsim phantom glenoid|block --out DIR [options]\n"
    "  glenoid               glenoid (40 x 29 mm face, 35 mm radius of curvature, 1.75 mm "
    "cortical\n"
    "                        shell at 1500 HU over 300 HU cancellous bone, 3.2 mm pilot hole)\n"
    "  block                 6 x 6 x 4 mm cortical block (1600 HU) in air, top face at z = 0\n"
    "  scapula               scapula with glenoid and humeral head (bmsim phantom scapula --help)\n"
    "  --out DIR             folder to create (must not exist or be empty; written atomically)\n"
    "  --compress SYNTAX     rle, jpeg-lossless, jpeg-ls or jpeg2000 (default: uncompressed)\n"
    "  --noise HU            Gaussian noise sigma (default 10)\n"
    "  --quiet               no progress bar\n";
}

namespace bm::cli {

ProgressFn TerminalProgress(bool quiet); // bmsimImport.cxx
#ifdef BM_PLANNING_WITH_IO
int ScapulaPhantomCommand(const Args& args); // bmsimPlan.cxx
#endif

static int PhantomCommand(const Args& args) {
#ifdef BM_PLANNING_WITH_IO
  if (std::find(args.begin(), args.end(), "scapula") != args.end())
    return ScapulaPhantomCommand(args);
#endif
  const ParsedArgs p(args, {"out", "compress", "noise"}, {"help", "quiet"},
                     {{"o", "out"}, {"h", "help"}, {"q", "quiet"}}, kUsage);
  if (p.Has("help")) {
    std::cout << kUsage;
    return 0;
  }
  bm::PhantomCTOptions ct;
  bm::DicomWriteOptions dicom;
  if (const auto syntax = p.Get("compress")) {
    dicom.transferSyntax = *syntax;
    if (dicom.transferSyntax != "rle" && dicom.transferSyntax != "jpeg-lossless" &&
        dicom.transferSyntax != "jpeg-ls" && dicom.transferSyntax != "jpeg2000")
      throw UsageError("--compress must be rle, jpeg-lossless, jpeg-ls or jpeg2000");
  }
  if (const auto noise = p.GetDouble("noise", -HUGE_VAL, HUGE_VAL)) {
    if (*noise < 0)
      throw UsageError("--noise must be >= 0");
    ct.noiseHU = *noise;
  }
  const bool quiet = p.Has("quiet");
  const auto& pos = p.Positional();
  if (pos.size() > 1)
    throw UsageError("more than one phantom name\n" + std::string(kUsage));
  const std::string name = pos.empty() ? "" : pos[0];
  if (name != "glenoid" && name != "block")
    throw UsageError("name the phantom: glenoid or block\n" + std::string(kUsage));
  const std::string out = p.Get("out", "");
  if (out.empty())
    throw UsageError("--out DIR is required\n" + std::string(kUsage));
  bm::PhantomInfo info =
      bm::WritePhantomSeries(name, out, ct, dicom, bm::Progress(TerminalProgress(quiet)));
  if (!quiet && isatty(2))
    std::fprintf(stderr, "\n");
  const auto& c = info.centreMm;
  const auto& n = info.axisOut;
  const auto& b = info.boneBounds;
  std::cout << std::fixed << std::setprecision(3) << "phantom:     " << name
            << " (DICOM series, CT)\n"
            << "wrote:       " << out << "\n"
            << "centre:      (" << c[0] << ", " << c[1] << ", " << c[2] << ") mm"
            << (name == "glenoid" ? " (glenoid face centre)" : " (top face centre)") << "\n"
            << "axis out:    (" << n[0] << ", " << n[1] << ", " << n[2]
            << ") (tools feed along minus this)\n"
            << "bone bounds: [" << b.lo[0] << ", " << b.hi[0] << "] x [" << b.lo[1] << ", "
            << b.hi[1] << "] x [" << b.lo[2] << ", " << b.hi[2] << "] mm\n"
            << "bone volume: " << info.boneVolumeMm3 << " mm^3 (analytic)\n";
  return 0;
}

BM_REGISTER_COMMAND(phantom, "write a synthetic CT (glenoid or block) as a DICOM series",
                    PhantomCommand);

} // namespace bm::cli
#endif
