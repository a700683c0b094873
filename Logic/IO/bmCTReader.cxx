// bmCTReader.cxx - see bmCTReader.h: the input's kind (DICOM folder or file, InVesalius project,
// volume file) to its reader, then the intensity decision and a tilted stack's resampling. The
// readers: bmCTReaderDicomScan.cxx, bmCTReaderDicomSeries.cxx, bmCTReaderVolume.cxx.
#include "bmCTReader.h"
#include "bmCTReaderInternal.h"

#include "bmDicomFileCheck.h"
#include "bmHeaderCheck.h"
#include "bmInvesaliusReader.h"
#include "bmTiltedStack.h"

#include <itkMacro.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <new>

namespace fs = std::filesystem;

namespace bm {

void UpdateHURange(CTImage& ct) {
  const float* p = ct.hu->GetBufferPointer();
  size_t n = ct.hu->GetLargestPossibleRegion().GetNumberOfPixels();
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (size_t i = 0; i < n; ++i) {
    lo = std::min(lo, p[i]);
    hi = std::max(hi, p[i]);
  }
  ct.huMin = lo;
  ct.huMax = hi;
}

namespace {

using ctreader::ReadDicomFile;
using ctreader::ReadDicomFolder;
using ctreader::ReadOutcome;
using ctreader::ReadVolumeFile;
using ctreader::ToLower;

/// A single file that is DICOM: the DICM magic, or a DICOM extension.
bool LooksLikeDicomFile(const fs::path& file) {
  std::string ext = ToLower(file.extension().string());
  return HasDicomMagic(file) || ext == ".dcm" || ext == ".dicom";
}

CTImage ReadCTUnguarded(const std::string& path, const ReadOptions& options,
                        const Progress& progress) {
  fs::path p(path);
  if (!fs::exists(p))
    throw std::runtime_error("'" + path + "' does not exist");
  ReadOutcome r;
  const Progress reading = progress.Range(0, 0.95);
  if (fs::is_directory(p)) {
    r = ReadDicomFolder(p, options, reading);
  } else {
    CheckRegularFile(p, "the input");
    std::string lower = ToLower(p.filename().string());
    if (lower.size() > 5 && lower.compare(lower.size() - 5, 5, ".inv3") == 0) {
      r.ct = ReadInvesaliusProject(path, options, reading);
      r.evidence.modality = r.ct.modality;
    } else if (LooksLikeDicomFile(p)) {
      r = ReadDicomFile(p, options, reading);
    } else {
      r = ReadVolumeFile(p, options, reading);
    }
  }
  CTImage& ct = r.ct;
  r.evidence.file = path;
  r.evidence.format = ct.format;
  ApplyIntensityDecision(ct, r.evidence, options.intensity);
  // A tilted DICOM stack (sheared grid): onto a grid along the slice normal, after the values were
  // judged as read (interpolation makes whole numbers fractional), air outside the stack.
  if (StackTiltDeg(ct.hu) > 1e-6) {
    ct.hu = ResampleTiltedStack(ct.hu, ct.huMin, options.maxMemoryBytes, progress.Range(0.95, 1));
    UpdateHURange(ct);
  }
  progress(1.0, "checking the values");
  return ct;
}

} // namespace

void ApplyIntensityDecision(CTImage& ct, IntensityEvidence ev, const IntensityOptions& options) {
  // Value range, and whether every value is whole.
  {
    const float* v = ct.hu->GetBufferPointer();
    const size_t n = ct.hu->GetLargestPossibleRegion().GetNumberOfPixels();
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    bool whole = true;
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(v[i]))
        throw std::runtime_error("'" + ev.file +
                                 "' holds a non-finite voxel value (NaN or infinite)");
      lo = std::min(lo, v[i]);
      hi = std::max(hi, v[i]);
      whole = whole && v[i] == std::nearbyint(v[i]);
    }
    ev.minValue = lo;
    ev.maxValue = hi;
    ev.allIntegers = whole;
  }
  ct.intensity = DecideIntensity(ev, options, ct.warnings);
  if (ct.intensity.kind == IntensityKind::GivenMapping) {
    float* v = ct.hu->GetBufferPointer();
    const size_t n = ct.hu->GetLargestPossibleRegion().GetNumberOfPixels();
    const double a = ct.intensity.slope, b = ct.intensity.intercept;
    for (size_t i = 0; i < n; ++i)
      v[i] = float(a * double(v[i]) + b);
  }
  UpdateHURange(ct);
}

CTImage ReadCT(const std::string& path, const ReadOptions& options, const Progress& progress) {
  // The boundary: every library failure becomes a message naming the input.
  try {
    return ReadCTUnguarded(path, options, progress);
  } catch (const Cancelled&) {
    throw;
  } catch (const itk::ExceptionObject& e) {
    throw std::runtime_error("cannot read '" + path + "': " + e.GetDescription());
  } catch (const std::bad_alloc&) {
    throw std::runtime_error("not enough memory to read '" + path +
                             "' (lower --max-memory's demand by cropping the CT, or free memory)");
  } catch (const std::filesystem::filesystem_error& e) {
    throw std::runtime_error("cannot read '" + path + "': " + e.what());
  } catch (const std::runtime_error&) {
    throw;
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read '" + path + "': " + e.what());
  }
}

} // namespace bm
