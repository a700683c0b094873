#include "bmSessionRecorder.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "bmAtomicFile.h"
#include "bmJson.h"

#ifdef BM_SESSION_HDF5
#include <hdf5.h>
#endif

namespace bm {

nlohmann::json SessionOptionsToJson(const SessionOptions& o, const DeviceLimits& l) {
  const ProxyOptions& p = o.proxy;
  return {{"rate_hz", o.rateHz},
          {"speed_rpm", o.speedRpm},
          {"method", ToString(p.method)},
          {"rendering", ToString(p.rendering)},
          {"coupling_stiffness_N_per_mm", p.coupling.stiffnessNPerMm},
          {"coupling_damping_Ns_per_mm", p.coupling.dampingNsPerMm},
          {"force_scale", p.coupling.forceScale},
          {"max_feed_mm_per_rev", p.maxFeedMmPerRev},
          {"catch_up_speed_mm_per_s", o.catchUpSpeedMmPerS},
          {"contact_stiffness_N_per_mm3", p.contactStiffnessPerArea},
          {"sdf_resolution", p.sdfResolution},
          {"max_step_voxels", p.maxStepVoxels},
          {"max_iterations", p.maxIterations},
          {"dead_band_voxels", p.deadBandVoxels},
          {"kim_cut_depth_voxels", p.kimCutDepthVoxels},
          {"device_limits",
           {{"max_force_N", l.maxForceN},
            {"max_stiffness_N_per_mm", l.maxStiffnessNPerMm},
            {"max_damping_Ns_per_mm", l.maxDampingNsPerMm},
            {"workspace_radius_mm", l.workspaceRadiusMm},
            {"rate_hz", l.rateHz}}}};
}

SessionOptions SessionOptionsFromJson(const nlohmann::json& j, DeviceLimits& l) {
  SessionOptions o;
  o.rateHz = j.value("rate_hz", o.rateHz);
  o.speedRpm = j.value("speed_rpm", o.speedRpm);
  ProxyOptions& p = o.proxy;
  p.method = ContactMethodFromString(j.value("method", std::string("cutting")));
  p.rendering = RenderingFromString(j.value("rendering", std::string("coupled")));
  p.coupling.stiffnessNPerMm = j.value("coupling_stiffness_N_per_mm", p.coupling.stiffnessNPerMm);
  p.coupling.dampingNsPerMm = j.value("coupling_damping_Ns_per_mm", p.coupling.dampingNsPerMm);
  // Recordings from before force scaling were unscaled.
  p.coupling.forceScale = j.value("force_scale", 1.0);
  p.maxFeedMmPerRev = j.value("max_feed_mm_per_rev", 1e30); // older recordings: no feed bound
  o.catchUpSpeedMmPerS = j.value("catch_up_speed_mm_per_s", o.catchUpSpeedMmPerS);
  p.contactStiffnessPerArea = j.value("contact_stiffness_N_per_mm3", p.contactStiffnessPerArea);
  p.sdfResolution = j.value("sdf_resolution", p.sdfResolution);
  p.maxStepVoxels = j.value("max_step_voxels", p.maxStepVoxels);
  p.maxIterations = j.value("max_iterations", p.maxIterations);
  p.deadBandVoxels = j.value("dead_band_voxels", p.deadBandVoxels);
  p.kimCutDepthVoxels = j.value("kim_cut_depth_voxels", p.kimCutDepthVoxels);
  if (j.contains("device_limits")) {
    const auto& d = j.at("device_limits");
    l.maxForceN = d.value("max_force_N", l.maxForceN);
    l.maxStiffnessNPerMm = d.value("max_stiffness_N_per_mm", l.maxStiffnessNPerMm);
    l.maxDampingNsPerMm = d.value("max_damping_Ns_per_mm", l.maxDampingNsPerMm);
    l.workspaceRadiusMm = d.value("workspace_radius_mm", l.workspaceRadiusMm);
    l.rateHz = d.value("rate_hz", l.rateHz);
  }
  return o;
}

namespace {
bool IsHdf5Path(const std::string& path) {
  const auto ext = std::filesystem::path(path).extension().string();
  return ext == ".h5" || ext == ".hdf5";
}
} // namespace

void WriteRecordingCsv(std::ostream& out, const Recording& r) {
  out << "# bmsession " << r.meta.dump() << '\n';
  const auto& cols = FrameRecord::Columns();
  for (size_t i = 0; i < cols.size(); ++i)
    out << (i ? "," : "") << cols[i];
  out << '\n' << std::setprecision(17);
  for (const auto& f : r.frames) {
    const auto row = f.ToRow();
    for (size_t i = 0; i < row.size(); ++i)
      out << (i ? "," : "") << row[i];
    out << '\n';
  }
}

void WriteRecordingCsv(const std::string& path, const Recording& r) {
  WriteFileAtomic(path, [&](std::ostream& out) { WriteRecordingCsv(out, r); });
}

#ifdef BM_SESSION_HDF5
namespace {
void WriteStringAttribute(hid_t obj, const char* name, const std::string& value) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, std::max<size_t>(1, value.size()));
  H5Tset_strpad(type, H5T_STR_NULLPAD);
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  herr_t st = attr < 0 ? -1 : H5Awrite(attr, type, value.data());
  if (attr >= 0)
    H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
  if (st < 0)
    throw std::runtime_error(std::string("HDF5: cannot write attribute ") + name);
}

std::string ReadStringAttribute(hid_t obj, const char* name) {
  hid_t attr = H5Aopen(obj, name, H5P_DEFAULT);
  if (attr < 0)
    throw std::runtime_error(std::string("HDF5: no attribute ") + name);
  hid_t type = H5Aget_type(attr);
  const size_t n = H5Tget_size(type);
  std::string s(n, '\0');
  hid_t mem = H5Tcopy(H5T_C_S1);
  H5Tset_size(mem, n);
  H5Tset_strpad(mem, H5T_STR_NULLPAD);
  const herr_t st = H5Aread(attr, mem, s.data());
  H5Tclose(mem);
  H5Tclose(type);
  H5Aclose(attr);
  if (st < 0)
    throw std::runtime_error(std::string("HDF5: cannot read attribute ") + name);
  while (!s.empty() && s.back() == '\0')
    s.pop_back();
  return s;
}
} // namespace
#endif

bool HasHdf5() {
#ifdef BM_SESSION_HDF5
  return true;
#else
  return false;
#endif
}

void WriteRecordingHdf5(const std::string& path, const Recording& r) {
#ifdef BM_SESSION_HDF5
  const std::string tmp = TemporarySibling(path);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  hid_t file = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0)
    throw std::runtime_error("HDF5: cannot create '" + tmp + "'");
  bool ok = false;
  try {
    const auto& cols = FrameRecord::Columns();
    std::vector<double> data;
    data.reserve(r.frames.size() * cols.size());
    for (const auto& f : r.frames) {
      const auto row = f.ToRow();
      data.insert(data.end(), row.begin(), row.end());
    }
    hsize_t dims[2] = {hsize_t(r.frames.size()), hsize_t(cols.size())};
    hid_t space = H5Screate_simple(2, dims, nullptr);
    hid_t ds =
        H5Dcreate2(file, "frames", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    herr_t st = ds < 0 ? -1
                       : (data.empty() ? 0
                                       : H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL,
                                                  H5P_DEFAULT, data.data()));
    std::string names;
    for (size_t i = 0; i < cols.size(); ++i)
      names += (i ? "," : "") + cols[i];
    if (ds >= 0) {
      WriteStringAttribute(ds, "columns", names);
      H5Dclose(ds);
    }
    H5Sclose(space);
    if (st < 0)
      throw std::runtime_error("HDF5: cannot write /frames to '" + tmp + "'");
    WriteStringAttribute(file, "meta", r.meta.dump());
    ok = H5Fclose(file) >= 0;
    file = -1;
    if (!ok)
      throw std::runtime_error("HDF5: cannot close '" + tmp + "'");
  } catch (...) {
    if (file >= 0)
      H5Fclose(file);
    std::remove(tmp.c_str());
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write '" + path + "': " + ec.message());
  }
#else
  (void)r;
  throw std::runtime_error("cannot write '" + path + "': this build has no HDF5 (BM_WITH_HDF5)");
#endif
}

void WriteRecording(const std::string& path, const Recording& r) {
  if (IsHdf5Path(path))
    WriteRecordingHdf5(path, r);
  else
    WriteRecordingCsv(path, r);
}

Recording ReadRecording(const std::string& path) {
  Recording rec;
  const size_t ncols = FrameRecord::Columns().size();
  if (IsHdf5Path(path)) {
#ifdef BM_SESSION_HDF5
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0)
      throw std::runtime_error("cannot open HDF5 recording '" + path + "'");
    try {
      rec.meta =
          ParseJson(ReadStringAttribute(file, "meta"), "the header of recording '" + path + "'");
      hid_t ds = H5Dopen2(file, "frames", H5P_DEFAULT);
      if (ds < 0)
        throw std::runtime_error("'" + path + "' has no /frames dataset");
      hid_t space = H5Dget_space(ds);
      hsize_t dims[2] = {0, 0};
      const int nd = H5Sget_simple_extent_dims(space, dims, nullptr);
      H5Sclose(space);
      if (nd != 2 || dims[1] != ncols) {
        H5Dclose(ds);
        throw std::runtime_error("'" + path + "': /frames has the wrong shape");
      }
      std::vector<double> data(size_t(dims[0] * dims[1]));
      const herr_t st =
          data.empty() ? 0
                       : H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
      H5Dclose(ds);
      if (st < 0)
        throw std::runtime_error("'" + path + "': cannot read /frames");
      for (size_t i = 0; i < dims[0]; ++i)
        rec.frames.push_back(FrameRecord::FromRow(
            std::vector<double>(data.begin() + i * ncols, data.begin() + (i + 1) * ncols)));
    } catch (...) {
      H5Fclose(file);
      throw;
    }
    H5Fclose(file);
    return rec;
#else
    throw std::runtime_error("cannot read '" + path + "': this build has no HDF5 (BM_WITH_HDF5)");
#endif
  }
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot read recording '" + path + "'");
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.rfind("# bmsession ", 0) == 0) {
      rec.meta =
          ParseJson(std::string_view(line).substr(12),
                    "the header of recording '" + path + "' (line " + std::to_string(lineNo) + ")");
      continue;
    }
    if (line.empty() || line[0] == '#' || line.rfind("frame,", 0) == 0)
      continue;
    std::vector<double> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) {
      try {
        row.push_back(std::stod(cell));
      } catch (const std::exception&) {
        throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": not a number");
      }
    }
    if (row.size() != ncols)
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": wrong column count");
    rec.frames.push_back(FrameRecord::FromRow(row));
  }
  if (rec.meta.is_null())
    throw std::runtime_error("'" + path + "' is not a session recording (no '# bmsession' line)");
  return rec;
}

} // namespace bm
