// bmPlanDicomResults.cxx - see bmPlanDicomResults.h.
#include "bmPlanDicomResults.h"

#include <cstring>
#include <utility>

#include <dcmtk/config/osconfig.h>

#include <dcmtk/dcmdata/dcuid.h>
#include <filesystem>
#include <stdexcept>

#include "bmDicomSecondaryCapture.h"
#include "bmDicomSegmentation.h"
#include "bmDicomSource.h"

namespace bm {

namespace {

struct Key {
  const char* section; // "measurements" (of the planning), "planning" or "outcome"
  const char* key;
  const char* code;
  const char* name;
  const char* unit;
  double scale;
  const char* method; // "" = the summary's own "methods" entry for the key, if any
};

const Key kKeys[] = {
    {"measurements", "friedman_version_deg", "version-2d", "Glenoid version (Friedman, 2D)", "deg",
     1, ""},
    {"measurements", "version_3d_deg", "version-3d", "Glenoid version (3D)", "deg", 1, ""},
    {"measurements", "inclination_deg", "inclination", "Glenoid inclination", "deg", 1, ""},
    {"measurements", "glenoid_height_mm", "height", "Glenoid height", "mm", 1,
     "rim extent along the face's superior-inferior axis"},
    {"measurements", "glenoid_width_mm", "width", "Glenoid width", "mm", 1,
     "rim extent across the face"},
    {"measurements", "face_radius_mm", "face-radius", "Glenoid face radius of curvature", "mm", 1,
     ""},
    {"planning", "correction_deg", "correction", "Planned correction of the reaming axis", "deg", 1,
     "angle between the face normal and the planned axis"},
    {"planning", "ream_depth_mm", "ream-depth", "Planned reaming depth", "mm", 1,
     "below the glenoid centre along the axis"},
    {"outcome", "removed_volume_mm3", "removed", "Bone removed", "mm3", 1,
     "voxmap before the steps less after"},
    {"outcome", "removed_cortical_mm3", "removed-cort", "Cortical bone removed", "mm3", 1,
     "voxels of material scale >= 0.5"},
    {"outcome", "removed_cancellous_mm3", "removed-canc", "Cancellous bone removed", "mm3", 1,
     "voxels of material scale < 0.5"},
    {"outcome", "reamed_face_angle_to_axis_deg", "face-angle",
     "Reamed face angle to the planned axis", "deg", 1, "least-squares plane of the reamed face"},
    {"outcome", "face_depth_mm", "face-depth", "Reamed face depth", "mm", 1,
     "where the axis crosses the reamed face's plane, below the centre"},
    {"outcome", "medialisation_mm", "medialisation", "Medialisation of the joint line", "mm", 1,
     "face height at the centre before less after"},
    {"outcome", "seating_fraction", "seating", "Baseplate seating", "%", 100,
     "baseplate back area with bone within the gap"},
    {"outcome", "bone_beyond_peg_mm", "beyond-peg", "Bone beyond the central peg's tip", "mm", 1,
     "along the axis to the vault's far cortex"},
};

} // namespace

std::vector<DicomMeasurement> PlanMeasurements(const nlohmann::json& summary) {
  std::vector<DicomMeasurement> out;
  const nlohmann::json planning = summary.value("planning", nlohmann::json::object());
  const nlohmann::json measured = planning.value("measurements", nlohmann::json::object());
  const nlohmann::json methods = measured.value("methods", nlohmann::json::object());
  const nlohmann::json outcome = summary.value("outcome", nlohmann::json::object());
  for (const Key& k : kKeys) {
    const nlohmann::json& sec = std::string(k.section) == "measurements" ? measured
                                : std::string(k.section) == "planning"   ? planning
                                                                         : outcome;
    if (!sec.is_object() || !sec.contains(k.key) || !sec[k.key].is_number())
      continue;
    DicomMeasurement m;
    m.code = k.code;
    m.name = k.name;
    m.value = k.scale * sec[k.key].get<double>();
    m.unit = k.unit;
    m.method = k.method;
    if (m.method.empty()) {
      // The summary names its methods by the key without its unit suffix.
      std::string base = k.key;
      for (const char* suffix : {"_deg", "_mm"})
        if (base.size() > std::strlen(suffix) &&
            base.compare(base.size() - std::strlen(suffix), std::string::npos, suffix) == 0)
          base.erase(base.size() - std::strlen(suffix));
      if (methods.contains(base) && methods[base].is_string())
        m.method = methods[base].get<std::string>();
    }
    out.push_back(m);
  }
  return out;
}

PlanDicomFiles WritePlanDicomResults(const std::string& dir, const std::string& dicomFolder,
                                     const std::string& seriesUID, const Voxmap& before,
                                     const Voxmap& after, const nlohmann::json& summary,
                                     const std::string& softwareVersion,
                                     const std::string& pictureDir) {
  const std::vector<DicomMeasurement> m = PlanMeasurements(summary);
  if (m.empty())
    throw std::runtime_error("DICOM results: the plan result holds no measurement");
  const DicomSource source = ReadDicomSource(dicomFolder, seriesUID);
  std::filesystem::create_directories(dir);
  PlanDicomFiles files;
  files.segmentation = (std::filesystem::path(dir) / "reamed-bone.seg.dcm").string();
  files.report = (std::filesystem::path(dir) / "plan.sr.dcm").string();
  DicomSegmentationInfo si;
  si.softwareVersion = softwareVersion;
  WriteReamingSegmentation(files.segmentation, source, before, after, si);
  DicomReportInfo ri;
  ri.softwareVersion = softwareVersion;
  ri.title = summary.value("plan", std::string("glenoid plan"));
  WriteMeasurementReport(files.report, source, m, ri);
  // The pictures the result shows, in a series of their own.
  const nlohmann::json pictures = summary.value("pictures", nlohmann::json::object());
  if (!pictureDir.empty() && pictures.is_object()) {
    DicomPictureInfo pi;
    pi.softwareVersion = softwareVersion;
    char uid[100];
    pi.seriesUID = dcmGenerateUniqueIdentifier(uid, SITE_SERIES_UID_ROOT);
    const std::pair<const char*, const char*> kinds[] = {
        {"before", "the glenoid before the steps, the plan drawn"},
        {"after", "the glenoid after the steps, the plan drawn"}};
    for (const auto& [key, text] : kinds) {
      if (!pictures.contains(key) || !pictures[key].is_string())
        continue;
      const std::string png =
          (std::filesystem::path(pictureDir) / pictures[key].get<std::string>()).string();
      const std::string sc =
          (std::filesystem::path(dir) / (std::string("glenoid_") + key + ".sc.dcm")).string();
      pi.description = text;
      WriteSecondaryCapture(sc, source, png, pi);
      files.pictures.push_back(sc);
      ++pi.instanceNumber;
    }
  }
  return files;
}

} // namespace bm
