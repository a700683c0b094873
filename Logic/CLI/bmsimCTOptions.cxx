// bmsimCTOptions.cxx - see bmsimCTOptions.h.
#include "bmsimCTOptions.h"
#include "bmsimCommand.h"

#ifdef BM_WITH_VTK
#include "bmCTVoxmap.h"
#include "bmVTKImageVolume.h"
#include "vtkImageData.h"
#endif

namespace bm::cli {

void AddCTOptions(ParsedArgs& p, CTOptionsFor command) {
  const bool plan = command == CTOptionsFor::Plan;
  p.Real("threshold", -1000, 4000, "HU", "bone threshold in Hounsfield units (default 200)")
      .Value("seed", "X,Y,Z",
             plan ? "world point (mm) on the scapula: the step scenes keep the bone there "
                    "(default: a point 1 mm under the glenoid centre)"
                  : "world point (mm) on the bone to keep (default: the largest bone)")
      .Value("exclude", "X,Y,Z[;X,Y,Z...]",
             plan ? "world points (mm) on bones the steps must not machine (a humeral head "
                    "joined to the glenoid at the threshold): the step scenes' bone is split from "
                    "them across the joint; detection still sees every bone"
                  : "world points (mm) on bones to drop: split from the kept bone across the "
                    "joint space (a point off all bone is a warning)")
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
            "memory the import may use (default 75 % of the memory this process may use: "
            "physical, or its cgroup limit)");
  if (!plan)
    p.Flag("keep-all", "keep every bone component, not only the largest");
  p.Flag("no-fill-holes", "do not fill cavities inside the bone");
}

ImportOptions CTOptionsFromArgs(const ParsedArgs& p, CTOptionsFor command) {
  ImportOptions opt;
  if (const auto t = p.GetDouble("threshold", -1000, 4000))
    opt.segmentation.thresholdHU = float(*t);
  if (const auto s = p.GetDoubles("seed", 3))
    opt.segmentation.seedMm = std::array<double, 3>{(*s)[0], (*s)[1], (*s)[2]};
  if (const auto r = p.GetDoubles("roi", 6))
    opt.roiMm = RoiFromCorners(*r, "--roi");
  if (const auto e = p.Get("exclude"))
    opt.segmentation.excludeSeedsMm = ParsePointsMm(*e, "--exclude");
  if (const auto b = p.Get("box"))
    opt.segmentation.box = OrientedBoxFromText(*b, "--box");
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
  // The plan keeps every bone: the humeral head across the joint shows where the glenoid is;
  // its seed is for the step scenes' bone, not for detection.
  if (command == CTOptionsFor::Plan) {
    opt.segmentation.keepAllComponents = true;
    opt.segmentation.seedMm.reset();
  } else {
    opt.segmentation.keepAllComponents = p.Has("keep-all");
  }
  opt.segmentation.fillHoles = !p.Has("no-fill-holes");
  return opt;
}

ImportResult ImportCT(const std::string& input, const ImportOptions& options,
                      const std::string& vtkCopy, bool& copied, const Progress& progress) {
  copied = false;
#ifdef BM_WITH_VTK
  if (IsVTKImageFile(input)) {
    const vtkSmartPointer<vtkImageData> image = ReadVTKImageFile(input);
    VTKImageVolume volume;
    VolumeFromVTKImage(image, input, volume);
    SaveCTVolume(volume.view, vtkCopy);
    copied = true;
    ImportResult r = ImportVoxmap(vtkCopy, options, progress);
    r.source = input;
    r.format = IsVTKImageFile(input) && input.size() >= 4 &&
                       input.compare(input.size() - 4, 4, ".vti") == 0
                   ? "VTK XML image data, read by VTK"
                   : "VTK legacy structured points, read by VTK";
    return r;
  }
#else
  (void)vtkCopy;
#endif
  return ImportVoxmap(input, options, progress);
}

} // namespace bm::cli
