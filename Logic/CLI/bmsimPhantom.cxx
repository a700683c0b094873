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
#include <string>
#include <vector>

namespace bm::cli {

ProgressFn TerminalProgress(bool quiet); // bmsimImport.cxx
#ifdef BM_PLANNING_WITH_IO
int ScapulaPhantomCommand(const ParsedArgs& p); // bmsimPlan.cxx
#endif

static void PhantomOptions(ParsedArgs& p) {
  p.Words("NAME",
          "glenoid: a glenoid (40 x 29 mm face, 35 mm radius of curvature, 1.75 mm cortical shell "
          "at 1500 HU over 300 HU cancellous bone, 3.2 mm pilot hole); block: a 6 x 6 x 4 mm "
          "cortical block (1600 HU) in air, top face at z = 0; shoulder: a humeral head (22 mm "
          "sphere) 3.5 mm across the joint from a glenoid plate, 1.5 mm cortical shells, blurred "
          "by the scanner's point spread so that the bones touch at the bone threshold (for bone "
          "separation: bmsim import --seed/--exclude); scapula: a scapula with its "
          "glenoid and a humeral head 4 mm across the joint, 1.5 mm cortical shells, 0.75 mm "
          "pixels, 1 mm slices, and DIR/truth.json (the analytic truth)")
      .Value("o,out", "DIR", "folder to create (must not exist or be empty; written atomically)")
      .Choice("compress", {"rle", "jpeg-lossless", "jpeg-ls", "jpeg2000"},
              "DICOM transfer syntax (default: uncompressed)")
      .Real("noise", 0, 1000, "HU", "Gaussian noise sigma (default 10)")
      .Real("blur", 0, 10, "MM",
            "scanner point spread, Gaussian sigma, mm (default: shoulder 1.5, glenoid and block "
            "none)")
      .Real("version", -45, 45, "DEG",
            "scapula: glenoid version, negative = retroversion (default -12)")
      .Real("inclination", -45, 45, "DEG",
            "scapula: glenoid inclination, positive = superior (default 8)")
      .Flag("b2", "scapula: posterior wear (biconcave Walch B2 face)")
      .Flag("left", "scapula: a left shoulder (default right)")
      .Real("cancellous-hu", -1000, 3000, "HU",
            "scapula: the cancellous bone's HU (default 300; below the bone threshold, as in "
            "osteoporotic bone, the cortex is a shell around a dark interior)")
      .Flag("humerus", "scapula: the humeral head as a proximal humerus (its articular cap on a "
                       "neck and shaft) instead of a whole ball")
      .Flag("arm-raised", "scapula: the arm raised above the head (a proximal humerus whose shaft "
                          "points up, the scapula turned 30 deg upward)")
      .Flag("spine", "scapula: with a scapular spine, whose root on the medial border is the "
                     "trigonum (default: the blade alone)")
      .Real("pixel-mm", 0.3, 3, "MM", "scapula: in-plane pixel size (default 0.75)")
      .Real("slice-mm", 0.5, 5, "MM",
            "scapula: slice thickness and spacing; each voxel averages the bone over its slice "
            "(partial volume; default 1)")
      .Real("joint-gap", 1, 20, "MM",
            "scapula: humeral head to glenoid face distance (default 4; at 1 a coarse scan "
            "joins the bones)")
      .Value("rotate", "RX,RY,RZ",
             "scapula: the patient turned about the glenoid centre, deg about x, y, z (each "
             "within 45; applied y, x, z)")
      .Flag("both", "scapula: both shoulders in one scan (the left the mirror image of the right)")
      .Value("window", "CENTRE,WIDTH",
             "scapula: store the CT as an 8-bit display window (HU) in DIR/ct.nrrd instead of a "
             "DICOM series, as some hospitals export it")
      .Value("axes", "I,J,K",
             "scapula, with --window: the volume stored along these world axes (a permutation "
             "of x, y, z, each optionally '-': -z stores the superior end at low slice indices), "
             "with the direction cosines that say so (default x,y,z)")
      .Flag("q,quiet", "no progress bar");
}

static int PhantomCommand(const ParsedArgs& p) {
  const auto& words = p.Positional();
#ifdef BM_PLANNING_WITH_IO
  if (std::find(words.begin(), words.end(), "scapula") != words.end())
    return ScapulaPhantomCommand(p);
#endif
  for (const char* o :
       {"version", "inclination", "b2", "left", "pixel-mm", "slice-mm", "joint-gap", "window",
        "rotate", "both", "spine", "humerus", "arm-raised", "cancellous-hu", "axes"})
    if (p.Has(o))
      throw UsageError(std::string("--") + o + " applies to the scapula phantom only");
  bm::PhantomCTOptions ct;
  bm::DicomWriteOptions dicom;
  if (const auto syntax = p.Get("compress")) {
    dicom.transferSyntax = *syntax;
    if (dicom.transferSyntax != "rle" && dicom.transferSyntax != "jpeg-lossless" &&
        dicom.transferSyntax != "jpeg-ls" && dicom.transferSyntax != "jpeg2000")
      throw UsageError("--compress must be rle, jpeg-lossless, jpeg-ls or jpeg2000");
  }
  if (const auto noise = p.GetDouble("noise", 0, 1000))
    ct.noiseHU = *noise;
  if (const auto blur = p.GetDouble("blur", 0, 10))
    ct.blurSigmaMm = *blur;
  const bool quiet = p.Has("quiet");
  const auto& pos = words;
  if (pos.size() > 1)
    throw UsageError("more than one phantom name");
  const std::string name = pos.empty() ? "" : pos[0];
  const std::vector<std::string> names = bm::PhantomNames();
  if (std::find(names.begin(), names.end(), name) == names.end())
    throw UsageError("name the phantom: glenoid, block, shoulder or scapula" +
                     (name.empty() ? std::string() : ", not '" + name + "'"));
  const std::string out = p.Get("out", "");
  if (out.empty())
    throw UsageError("--out DIR is required");
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
            << (name == "glenoid"    ? " (glenoid face centre)"
                : name == "shoulder" ? " (the glenoid plate's face centre)"
                                     : " (top face centre)")
            << "\n"
            << "axis out:    (" << n[0] << ", " << n[1] << ", " << n[2]
            << ") (tools feed along minus this)\n"
            << "bone bounds: [" << b.lo[0] << ", " << b.hi[0] << "] x [" << b.lo[1] << ", "
            << b.hi[1] << "] x [" << b.lo[2] << ", " << b.hi[2] << "] mm\n"
            << "bone volume: " << info.boneVolumeMm3 << " mm^3 (analytic)\n";
  return 0;
}

BM_REGISTER_COMMAND(phantom,
                    "write a synthetic CT (glenoid, block, shoulder or scapula) as a DICOM series",
                    PhantomOptions, PhantomCommand);

} // namespace bm::cli
#endif
