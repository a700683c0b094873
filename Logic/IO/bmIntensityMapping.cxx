#include "bmIntensityMapping.h"

#include "bmBoneSegmenter.h"
#include "bmVoxmapResampler.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace bm {

namespace {

std::string Num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

const char* kOverrides =
    "; if you know how to read them, import with --raw-threshold V (bone = values >= V in the "
    "file's own units; the material scale is then uniform, not calibrated) or with --hu-mapping "
    "SLOPE,INTERCEPT (HU = SLOPE x value + INTERCEPT)";

} // namespace

std::string IntensityMapping::Key() const {
  switch (kind) {
  case IntensityKind::HU:
    return "hu";
  case IntensityKind::GivenMapping:
    return "given-mapping";
  case IntensityKind::Raw:
    return "raw";
  }
  return "hu";
}

std::string IntensityMapping::Describe() const {
  std::ostringstream os;
  switch (kind) {
  case IntensityKind::HU:
    os << "Hounsfield units (" << basis << "); material scale calibrated from HU";
    break;
  case IntensityKind::GivenMapping:
    os << "HU = " << slope << " x value + " << intercept
       << " (given mapping); material scale calibrated from the mapped HU";
    break;
  case IntensityKind::Raw:
    os << "raw values, bone threshold " << rawThreshold
       << " in the file's units (given); material scale uniform (1), not calibrated";
    break;
  }
  return os.str();
}

IntensityMapping DecideIntensity(const IntensityEvidence& e, const IntensityOptions& o,
                                 std::vector<std::string>& warnings) {
  IntensityMapping m;
  if (o.huMapping && o.rawThreshold)
    throw std::runtime_error("give either a raw threshold or an HU mapping, not both");
  if (o.huMapping) {
    const auto [a, b] = *o.huMapping;
    if (!std::isfinite(a) || !std::isfinite(b) || a == 0)
      throw std::runtime_error("the HU mapping (slope " + Num(a) + ", intercept " + Num(b) +
                               ") must have a finite, non-zero slope and a finite intercept");
    m.kind = IntensityKind::GivenMapping;
    m.slope = a;
    m.intercept = b;
    m.basis = "given mapping";
    return m;
  }
  if (o.rawThreshold) {
    if (!std::isfinite(*o.rawThreshold))
      throw std::runtime_error("the raw threshold must be a finite number");
    m.kind = IntensityKind::Raw;
    m.rawThreshold = *o.rawThreshold;
    m.materialCalibrated = false;
    m.basis = "raw values as asked";
    return m;
  }
  const std::string what = "'" + e.file + "'";
  const std::string range = Num(e.minValue) + " .. " + Num(e.maxValue);
  if (!e.hasRescale && e.storedInteger && e.storedBits == 8)
    throw std::runtime_error(what + " holds 8-bit values (" + range +
                             ") with no rescale slope/intercept: a windowed display image, not "
                             "Hounsfield units; a CT in HU needs air near -1000 and bone above "
                             "200" +
                             kOverrides);
  if (!e.hasRescale && e.allIntegers && e.minValue >= 0 && e.maxValue <= 255)
    throw std::runtime_error(what + " holds only whole values within 0 .. 255 (" + range +
                             ") and no rescale slope/intercept: a windowed 8-bit image, not "
                             "Hounsfield units (air near -1000, bone above 200)" +
                             kOverrides);
  if (!e.rescaleType.empty() && e.rescaleType != "HU" && !e.modality.empty() && e.modality != "CT")
    throw std::runtime_error(what + " has RescaleType '" + e.rescaleType + "' and modality '" +
                             e.modality + "': its values are not Hounsfield units" + kOverrides);
  if (e.format == "DICOM" && e.modality == "CT" && e.hasRescale)
    m.basis = "DICOM CT, rescale slope/intercept applied" +
              (e.rescaleType.empty() ? std::string() : ", RescaleType " + e.rescaleType);
  else if (e.minValue <= -500)
    m.basis = e.format + (e.modality.empty() ? "" : " " + e.modality) + ", values reach " +
              Num(e.minValue) + " (air near -1000 HU)";
  else
    m.basis = e.format + ", values " + range + " taken as HU";
  if (e.maxValue < 200)
    warnings.push_back("the highest value is " + Num(e.maxValue) +
                       ", below any bone in Hounsfield units: check that this is a CT in HU");
  else if (e.minValue >= 0 && e.maxValue > 1000)
    warnings.push_back("no value is below 0 (air is near -1000 HU, fat near -100 HU): the values "
                       "may be stored pixel values rather than Hounsfield units (--hu-mapping "
                       "1,-1024 reads the usual offset)");
  return m;
}

void AdjustForIntensity(const IntensityMapping& m, SegmentationOptions& seg,
                        MaterialMapping& material) {
  if (m.kind != IntensityKind::Raw)
    return;
  seg.thresholdHU = float(m.rawThreshold);
  seg.valueUnit = "(the file's units)";
  seg.holeMinMeanHU = -std::numeric_limits<float>::max();
  seg.metalHU = std::numeric_limits<float>::infinity(); // no HU: metal is not told from cortex
  material.corticalHU = 1.0f;
  material.minScale = 1.0f; // clamp(x, 1, 1): uniform 1 whatever the raw value
}

} // namespace bm
