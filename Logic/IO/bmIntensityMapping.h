// bmIntensityMapping.h - what a CT's voxel values mean: Hounsfield units, a given mapping to HU, or
// raw values in the file's own units (Docs/CTImport.md, "Intensities").
//
// The reader gathers the evidence (format, modality, rescale tags, stored pixel type, value range)
// and DecideIntensity picks the mapping, first rule that applies:
//  1. the user gave a mapping (IntensityOptions::huMapping): HU = slope x value + intercept;
//  2. the user asked for raw values (IntensityOptions::rawThreshold): no HU, the bone threshold is
//     in the file's units and the material scale is uniform (1, not calibrated);
//  3. clearly not HU -> refused with a message saying why and naming both overrides:
//     - stored as 8-bit integers with no rescale slope/intercept (a windowed display image), or
//     - no rescale, every value an integer within 0 .. 255 (the same, stored wider), or
//     - DICOM RescaleType (0028,1054) other than HU with a modality other than CT;
//  4. otherwise HU (DICOM CT rescaled by its own slope/intercept, or a volume whose values look
//  like
//     HU: air near -1000), with a warning when the range looks odd (no value below 0, or none above
//     200 HU).
// A non-finite rescale slope or intercept is refused by the reader before this point.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace bm {

struct SegmentationOptions;
struct MaterialMapping;

/// How the user says to read values that are not HU (both unset = decide from the file).
struct IntensityOptions {
  /// Use the values as stored; bone = values at or above this threshold, in the file's units.
  std::optional<double> rawThreshold;
  /// Map values to HU: {slope, intercept}, HU = slope x value + intercept (slope != 0, finite).
  std::optional<std::array<double, 2>> huMapping;
};

enum class IntensityKind {
  HU,           ///< the values are Hounsfield units (as read, or by the file's rescale)
  GivenMapping, ///< the user's mapping turned the values into HU
  Raw           ///< values in the file's units; thresholds in those units; material uniform
};

/// The mapping that was used, as recorded in the import summary and the voxmap file.
struct IntensityMapping {
  IntensityKind kind = IntensityKind::HU;
  /// Why this mapping (e.g. "DICOM CT, RescaleType HU", "values reach -1000 (air)").
  std::string basis = "values taken as Hounsfield units";
  double slope = 1.0, intercept = 0.0; ///< GivenMapping: HU = slope x value + intercept
  double rawThreshold = std::numeric_limits<double>::quiet_NaN(); ///< Raw: bone threshold
  /// True when the material scale comes from HU (kind HU or GivenMapping); false for Raw (uniform).
  bool materialCalibrated = true;

  /// "hu", "given-mapping" or "raw" (the voxmap file's bm_intensity_mapping field).
  std::string Key() const;
  /// One line for the summary, e.g. "raw values (threshold 128 in the file's units) ...".
  std::string Describe() const;
};

/// What a reader found out about the values.
struct IntensityEvidence {
  std::string file;                  ///< path named in messages
  std::string format;                ///< "DICOM", "NRRD", ...
  std::string modality;              ///< DICOM/MetaImage modality ("" = not stated)
  bool hasRescale = false;           ///< the file gives a rescale slope/intercept (DICOM, NIfTI)
  std::string rescaleType;           ///< DICOM RescaleType (0028,1054), "" when absent
  int storedBits = 0;                ///< bits per stored value (0 = unknown)
  bool storedInteger = true;         ///< integer stored values (false: float)
  double minValue = 0, maxValue = 0; ///< value range after the file's own rescale
  bool allIntegers = true;           ///< every value is an integer (after the file's own rescale)
};

/// Decide the mapping (rules above). Throws std::runtime_error when the values are clearly not HU
/// and no option says how to read them, and when both options are given or one is invalid.
/// warnings receives remarks on an odd HU range.
IntensityMapping DecideIntensity(const IntensityEvidence& evidence, const IntensityOptions& options,
                                 std::vector<std::string>& warnings);

/// Segmentation and material options for a mapping: Raw sets the bone threshold to the raw
/// threshold, fills holes whatever their mean value, and makes the material scale uniform (1);
/// HU and GivenMapping leave the options unchanged.
void AdjustForIntensity(const IntensityMapping& mapping, SegmentationOptions& segmentation,
                        MaterialMapping& material);

} // namespace bm
