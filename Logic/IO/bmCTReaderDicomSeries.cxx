// bmCTReaderDicomSeries.cxx - a DICOM series read into a CT: its slices checked (modality,
// pixel spacing, positions, orientation, size, rescale), ordered along the slice normal, their
// spacing and the stack's tilt checked, then each slice's pixels decoded through ITK's GDCMImageIO
// (bmCTReaderInternal.h; the folder's scan: bmCTReaderDicomScan.cxx).
#include "bmCTReaderInternal.h"

#include <itkGDCMImageIO.h>
#include <itkImageFileReader.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace fs = std::filesystem;

namespace bm::ctreader {

namespace {

double Dot(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// Largest angle between the slice positions' line and the slice normal (gantry tilts reach 30).
constexpr double kMaxTiltDeg = 45;

ReadOutcome ReadDicomSeries(const fs::path& dir, std::vector<SliceHeader>& slices,
                            const ReadOptions& opt, const Progress& progress) {
  const SliceHeader& first = slices.front();
  const std::string where = "DICOM series " + first.seriesId + " in '" + dir.string() + "'";

  if (first.modality != "CT" && !opt.allowNonCT)
    throw std::runtime_error(where + " has modality '" + first.modality +
                             "', not CT: only CT gives Hounsfield units for bone segmentation");
  for (const auto& s : slices) {
    const std::string f = "'" + s.file.filename().string() + "' of " + where;
    if (!s.frames.empty() && std::atoi(s.frames.c_str()) > 1)
      throw std::runtime_error(f +
                               " is a multi-frame image; only single-frame slices are supported");
    if (s.pixelSpacing.size() != 2)
      throw std::runtime_error(f +
                               " has no valid PixelSpacing (0028,0030): the voxel size is unknown");
    if (!(s.pixelSpacing[0] > 0 && s.pixelSpacing[1] > 0) || !std::isfinite(s.pixelSpacing[0]) ||
        !std::isfinite(s.pixelSpacing[1]))
      throw std::runtime_error(f + " has a zero or negative PixelSpacing (0028,0030)");
    if (s.ipp.size() != 3)
      throw std::runtime_error(
          f + " has no ImagePositionPatient (0020,0032): slices cannot be ordered");
    if (!std::all_of(s.ipp.begin(), s.ipp.end(), [](double v) { return std::isfinite(v); }))
      throw std::runtime_error(f + " has a non-finite ImagePositionPatient (0020,0032)");
    if (s.iop.size() != 6)
      throw std::runtime_error(f + " has no ImageOrientationPatient (0020,0037)");
    if (!std::all_of(s.iop.begin(), s.iop.end(), [](double v) { return std::isfinite(v); }))
      throw std::runtime_error(f + " has a non-finite ImageOrientationPatient (0020,0037)");
    if (s.modality != first.modality)
      throw std::runtime_error(f + " has modality '" + s.modality +
                               "', unlike the series' first "
                               "slice ('" +
                               first.modality + "')");
    for (const auto* v : {&s.rescaleSlope, &s.rescaleIntercept})
      if (!v->empty() && (v->size() != 1 || !std::isfinite(v->front())))
        throw std::runtime_error(
            f + " has an invalid or non-finite Rescale" +
            (v == &s.rescaleSlope ? "Slope (0028,1053)" : "Intercept (0028,1052)"));
    if (!s.rescaleSlope.empty() && s.rescaleSlope.front() == 0)
      throw std::runtime_error(f + " has a RescaleSlope (0028,1053) of 0");
    if (s.rows != first.rows || s.cols != first.cols)
      throw std::runtime_error(
          f + " is " + std::to_string(s.cols) + " x " + std::to_string(s.rows) +
          " pixels, unlike the series' first slice (" + std::to_string(first.cols) + " x " +
          std::to_string(first.rows) + ")");
    for (int a = 0; a < 6; ++a)
      if (std::abs(s.iop[a] - first.iop[a]) > 1e-4)
        throw std::runtime_error(f + " has an orientation different from the other slices");
    for (int a = 0; a < 2; ++a)
      if (std::abs(s.pixelSpacing[a] - first.pixelSpacing[a]) > 1e-6 * first.pixelSpacing[a] + 1e-9)
        throw std::runtime_error(f + " has a pixel spacing different from the other slices");
  }
  if (slices.size() < 2)
    throw std::runtime_error(where + " has a single slice: a volume needs at least two");

  // Orientation: the row and column directions must be unit vectors at right angles (GDCM's
  // tolerance, 0.001); a skewed or scaled pair would shrink or shear the volume.
  std::array<double, 3> r{first.iop[0], first.iop[1], first.iop[2]},
      c{first.iop[3], first.iop[4], first.iop[5]};
  {
    const std::string f = "'" + first.file.filename().string() + "' of " + where;
    const double lr = std::sqrt(Dot(r, r)), lc = std::sqrt(Dot(c, c)), rc = Dot(r, c);
    for (const auto& [len, which] : {std::pair{lr, "row"}, std::pair{lc, "column"}})
      if (std::abs(len - 1) > kOrientationTolerance) {
        std::ostringstream os;
        os << f << ": the " << which << " direction of its ImageOrientationPatient (0020,0037) has "
           << "length " << len << ", not 1 (direction cosines are unit vectors)";
        throw std::runtime_error(os.str());
      }
    if (std::abs(rc) > kOrientationTolerance) {
      std::ostringstream os;
      os << f << ": the row and column directions of its ImageOrientationPatient (0020,0037) are "
         << std::acos(std::clamp(rc / (lr * lc), -1.0, 1.0)) * 180 / M_PI
         << " deg apart, not 90 (row . column = " << rc << ")";
      throw std::runtime_error(os.str());
    }
    // Within the tolerance: make them exactly orthonormal for the image's direction matrix.
    for (auto& v : r)
      v /= lr;
    const double rc1 = Dot(r, c);
    for (int a = 0; a < 3; ++a)
      c[size_t(a)] -= rc1 * r[size_t(a)];
    const double lc1 = std::sqrt(Dot(c, c));
    for (auto& v : c)
      v /= lc1;
  }
  // Slice ordering along the normal = row direction x column direction.
  std::array<double, 3> n{r[1] * c[2] - r[2] * c[1], r[2] * c[0] - r[0] * c[2],
                          r[0] * c[1] - r[1] * c[0]};
  for (auto& s : slices)
    s.position = s.ipp[0] * n[0] + s.ipp[1] * n[1] + s.ipp[2] * n[2];
  std::sort(slices.begin(), slices.end(),
            [](const SliceHeader& a, const SliceHeader& b) { return a.position < b.position; });
  const size_t ns = slices.size();
  const double meanGap = (slices.back().position - slices.front().position) / double(ns - 1);
  for (size_t i = 0; i + 1 < ns; ++i) {
    double gap = slices[i + 1].position - slices[i].position;
    if (gap < 1e-3)
      throw std::runtime_error(where + ": slices '" + slices[i].file.filename().string() +
                               "' and '" + slices[i + 1].file.filename().string() +
                               "' lie at the same position");
    double tol = std::max(opt.sliceGapToleranceMm, opt.sliceGapToleranceRel * meanGap);
    if (std::abs(gap - meanGap) > tol) {
      std::ostringstream os;
      os << where << " has inconsistent slice spacing: the gap between '"
         << slices[i].file.filename().string() << "' and '"
         << slices[i + 1].file.filename().string() << "' is " << gap << " mm while the mean gap is "
         << meanGap << " mm (a slice may be missing)";
      throw std::runtime_error(os.str());
    }
  }
  // The positions must step uniformly (along a line): along the normal, or, with gantry tilt or
  // sheared positions, along a line at an angle to it (resampled after reading, bmTiltedStack.h).
  std::array<double, 3> step;
  for (int a = 0; a < 3; ++a)
    step[size_t(a)] =
        (slices.back().ipp[size_t(a)] - slices.front().ipp[size_t(a)]) / double(ns - 1);
  const double stepLen = std::sqrt(Dot(step, step));
  for (size_t k = 1; k + 1 < ns; ++k) {
    double off = 0;
    for (int a = 0; a < 3; ++a) {
      const double e =
          slices[k].ipp[size_t(a)] - slices.front().ipp[size_t(a)] - double(k) * step[size_t(a)];
      off += e * e;
    }
    off = std::sqrt(off);
    if (off > std::max(opt.sliceGapToleranceMm, opt.sliceGapToleranceRel * stepLen)) {
      std::ostringstream os;
      os << "'" << slices[k].file.filename().string() << "' of " << where << " lies " << off
         << " mm off the line through the other slices' positions (ImagePositionPatient): slice "
            "positions must step uniformly";
      throw std::runtime_error(os.str());
    }
  }
  // Gantry tilt or shear: the step's part in the slice plane, over the whole stack.
  const double inPlaneStep = std::sqrt(std::max(0.0, stepLen * stepLen - meanGap * meanGap));
  const double tiltDeg = std::atan2(inPlaneStep, meanGap) * 180 / M_PI;
  const bool tilted =
      inPlaneStep * double(ns - 1) > 0.1 * std::min(first.pixelSpacing[0], first.pixelSpacing[1]);
  if (tilted && tiltDeg > kMaxTiltDeg) {
    std::ostringstream os;
    os << where << ": its slice positions move " << tiltDeg
       << " deg away from the slice normal, more than the " << kMaxTiltDeg
       << " deg a gantry tilt reaches (ImagePositionPatient or ImageOrientationPatient is wrong)";
    throw std::runtime_error(os.str());
  }

  const uint64_t bytes =
      uint64_t(first.rows) * first.cols * ns * (sizeof(float) + opt.extraBytesPerVoxel);
  CheckMemoryBudget(bytes, opt.maxMemoryBytes,
                    "the CT (" + std::to_string(first.cols) + " x " + std::to_string(first.rows) +
                        " x " + std::to_string(ns) + " voxels" +
                        (opt.extraBytesPerVoxel ? ", with the import's working memory" : "") + ")");

  ReadOutcome out;
  CTImage& ct = out.ct;
  ct.source = dir.string();
  ct.format = "DICOM";
  ct.modality = first.modality;
  ct.seriesUID = first.seriesId;
  ct.seriesDescription = first.description;
  ct.transferSyntax = first.transferSyntax;
  ct.numFiles = int(ns);
  ct.hu = HUImage::New();
  HUImage::RegionType region;
  region.SetSize({{size_t(first.cols), size_t(first.rows), ns}});
  ct.hu->SetRegions(region);
  HUImage::SpacingType sp;
  sp[0] = first.pixelSpacing[1]; // PixelSpacing = row spacing \ column spacing
  sp[1] = first.pixelSpacing[0];
  sp[2] = tilted ? stepLen : meanGap; // tilted: one slice position to the next
  ct.hu->SetSpacing(sp);
  HUImage::PointType origin;
  for (int a = 0; a < 3; ++a)
    origin[a] = slices.front().ipp[a];
  ct.hu->SetOrigin(origin);
  HUImage::DirectionType dirm;
  for (int a = 0; a < 3; ++a) {
    dirm[a][0] = r[a];
    dirm[a][1] = c[a];
    dirm[a][2] = tilted ? step[size_t(a)] / stepLen : n[a];
  }
  ct.hu->SetDirection(dirm);
  ct.hu->Allocate();

  using SliceImage = itk::Image<float, 3>;
  const size_t perSlice = size_t(first.cols) * first.rows;
  for (size_t k = 0; k < ns; ++k) {
    progress(double(k) / ns, "reading DICOM");
    auto io = itk::GDCMImageIO::New();
    auto reader = itk::ImageFileReader<SliceImage>::New();
    reader->SetImageIO(io);
    reader->SetFileName(slices[k].file.string());
    try {
      reader->Update();
    } catch (const itk::ExceptionObject& e) {
      throw std::runtime_error("cannot read the pixels of '" + slices[k].file.string() +
                               "' (truncated or corrupt DICOM file): " + e.GetDescription());
    }
    SliceImage* img = reader->GetOutput();
    auto s = img->GetLargestPossibleRegion().GetSize();
    if (s[0] != size_t(first.cols) || s[1] != size_t(first.rows) || s[2] != 1)
      throw std::runtime_error("'" + slices[k].file.string() + "' decoded to an unexpected size");
    std::copy_n(img->GetBufferPointer(), perSlice, ct.hu->GetBufferPointer() + k * perSlice);
  }
  progress(1.0, "reading DICOM");
  if (tilted) {
    std::ostringstream os;
    os.precision(3);
    os << "the slice positions move " << tiltDeg
       << " deg off the slice normal (gantry tilt or sheared positions): the slices were "
          "resampled onto a grid along the normal, "
       << meanGap << " mm apart (linear interpolation, every voxel at its place)";
    ct.notes.push_back(os.str());
  }
  if (first.seriesUID.empty())
    ct.notes.push_back("the series has no SeriesInstanceUID (0020,000E): its " +
                       std::to_string(ns) +
                       " slices were grouped by SeriesNumber, "
                       "ImageOrientationPatient, Rows/Columns, StudyInstanceUID and Modality as "
                       "series " +
                       first.seriesId);
  IntensityEvidence& ev = out.evidence;
  ev.modality = first.modality;
  ev.hasRescale = !first.rescaleSlope.empty() || !first.rescaleIntercept.empty();
  ev.rescaleType = first.rescaleType;
  ev.storedBits = first.bitsAllocated;
  ev.storedInteger = true;
  return out;
}

} // namespace

ReadOutcome ReadDicomFolder(const fs::path& dir, const ReadOptions& opt, const Progress& progress) {
  ScannedFolder scanned = ScanFolder(dir, progress.Range(0, 0.1));
  std::vector<SliceHeader>& slices = ChooseSeries(scanned, dir, opt);
  CheckNoSliceWithoutImage(scanned, slices, dir);
  ReadOutcome r = ReadDicomSeries(dir, slices, opt, progress.Range(0.1, 1));
  if (!scanned.notDicom.empty())
    r.ct.notes.push_back(SkippedText(scanned.notDicom) + " (in '" + dir.string() + "')");
  return r;
}

/// A single DICOM file: the series it belongs to in its folder.
ReadOutcome ReadDicomFile(const fs::path& file, const ReadOptions& opt, const Progress& progress) {
  SliceHeader h = ReadSliceHeader(file);
  if (!h.hasPixelData)
    throw std::runtime_error("'" + file.string() + "' is a DICOM file without an image");
  if (!h.frames.empty() && std::atoi(h.frames.c_str()) > 1)
    throw std::runtime_error("'" + file.string() + "' is a multi-frame DICOM image (" + h.frames +
                             " frames); only series of single-frame slices are supported");
  const fs::path dir = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  ScannedFolder scanned = ScanFolder(dir, progress.Range(0, 0.1), true);
  auto it = scanned.series.find(h.seriesId);
  if (it == scanned.series.end())
    throw std::runtime_error("'" + file.string() + "': its series was not found in its folder");
  if (!opt.seriesUID.empty() && opt.seriesUID != h.seriesId)
    throw std::runtime_error("'" + file.string() + "' belongs to series " + h.seriesId + ", not " +
                             opt.seriesUID);
  CheckNoSliceWithoutImage(scanned, it->second, dir);
  ReadOutcome r = ReadDicomSeries(dir, it->second, opt, progress.Range(0.1, 1));
  r.ct.notes.push_back("'" + file.filename().string() + "' is one slice of series " + h.seriesId +
                       ": its " + std::to_string(r.ct.numFiles) + " slices in '" + dir.string() +
                       "' were read");
  return r;
}

} // namespace bm::ctreader
