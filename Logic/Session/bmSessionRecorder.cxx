#include "bmSessionRecorder.h"

#include "bmRegularFile.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "bmAtomicFile.h"
#include "bmJson.h"
#include "bmCsv.h"

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
          {"relax_tolerance_mm", p.relaxToleranceMm},
          {"dead_band_voxels", p.deadBandVoxels},
          {"kim_cut_depth_voxels", p.kimCutDepthVoxels},
          {"lateral_average_revolutions", p.lateralAverageRevolutions},
          {"device_limits",
           {{"max_force_N", l.maxForceN},
            {"max_stiffness_N_per_mm", l.maxStiffnessNPerMm},
            {"max_damping_Ns_per_mm", l.maxDampingNsPerMm},
            {"workspace_radius_mm", l.workspaceRadiusMm},
            {"rate_hz", l.rateHz}}}};
}

namespace {
// The value of field `key` of `j` (or `def` when absent), checked to be a number in [lo, hi]
// (lo excluded when openLo): a recording's header is user input that reaches the physics.
double Field(const nlohmann::json& j, const char* key, double def, double lo, double hi,
             const std::string& where, bool openLo = false) {
  if (!j.contains(key))
    return def;
  const nlohmann::json& v = j.at(key);
  if (!v.is_number())
    throw std::runtime_error(where + " field '" + key + "' must be a number");
  const double x = v.get<double>();
  if (!(openLo ? x > lo : x >= lo) || !(x <= hi)) {
    std::ostringstream m;
    m << where << " field '" << key << "' must be in " << (openLo ? "(" : "[") << lo << ", " << hi
      << "], got " << x;
    throw std::runtime_error(m.str());
  }
  return x;
}

std::string Text(const nlohmann::json& j, const char* key, const std::string& def,
                 const std::string& where) {
  if (!j.contains(key))
    return def;
  if (!j.at(key).is_string())
    throw std::runtime_error(where + " field '" + key + "' must be a string");
  return j.at(key).get<std::string>();
}
} // namespace

SessionOptions SessionOptionsFromJson(const nlohmann::json& j, DeviceLimits& l) {
  const std::string where = "the recording's session";
  if (!j.is_object())
    throw std::runtime_error(where + " must be a JSON object");
  SessionOptions o;
  o.rateHz = Field(j, "rate_hz", o.rateHz, 1, 1e7, where);
  o.speedRpm = Field(j, "speed_rpm", o.speedRpm, -1, 100000, where);
  ProxyOptions& p = o.proxy;
  try {
    p.method = ContactMethodFromString(Text(j, "method", "cutting", where));
    p.rendering = RenderingFromString(Text(j, "rendering", "coupled", where));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(where + ": " + e.what());
  }
  p.coupling.stiffnessNPerMm =
      Field(j, "coupling_stiffness_N_per_mm", p.coupling.stiffnessNPerMm, -1, 1000, where);
  p.coupling.dampingNsPerMm =
      Field(j, "coupling_damping_Ns_per_mm", p.coupling.dampingNsPerMm, -1, 100, where);
  // Recordings from before force scaling were unscaled.
  p.coupling.forceScale = Field(j, "force_scale", 1.0, 1e-3, kMaxForceScale, where);
  // Older recordings: no feed bound.
  p.maxFeedMmPerRev = Field(j, "max_feed_mm_per_rev", 1e30, 0, 1e30, where, true);
  o.catchUpSpeedMmPerS = Field(j, "catch_up_speed_mm_per_s", o.catchUpSpeedMmPerS, 0, 10000, where);
  p.contactStiffnessPerArea =
      Field(j, "contact_stiffness_N_per_mm3", p.contactStiffnessPerArea, 0, 1e7, where);
  p.sdfResolution = int(Field(j, "sdf_resolution", p.sdfResolution, 8, 512, where));
  p.maxStepVoxels = Field(j, "max_step_voxels", p.maxStepVoxels, 0, 100, where, true);
  p.maxIterations = int(Field(j, "max_iterations", p.maxIterations, 1, 1000, where));
  // Older recordings: the solve stopped at steps under 1e-9 mm.
  p.relaxToleranceMm = Field(j, "relax_tolerance_mm", 1e-9, 0, 1, where);
  p.deadBandVoxels = Field(j, "dead_band_voxels", p.deadBandVoxels, 0, 100, where);
  p.kimCutDepthVoxels = Field(j, "kim_cut_depth_voxels", p.kimCutDepthVoxels, 0, 100, where);
  // Older recordings: the lateral force acted frame by frame.
  p.lateralAverageRevolutions = Field(j, "lateral_average_revolutions", 0.0, 0, 100, where);
  if (j.contains("device_limits")) {
    const auto& d = j.at("device_limits");
    const std::string dw = "the recording's device_limits";
    if (!d.is_object())
      throw std::runtime_error(dw + " must be a JSON object");
    l.maxForceN = Field(d, "max_force_N", l.maxForceN, 0, 100, dw, true);
    l.maxStiffnessNPerMm =
        Field(d, "max_stiffness_N_per_mm", l.maxStiffnessNPerMm, 0, 100, dw, true);
    l.maxDampingNsPerMm = Field(d, "max_damping_Ns_per_mm", l.maxDampingNsPerMm, 0, 100, dw);
    l.workspaceRadiusMm = Field(d, "workspace_radius_mm", l.workspaceRadiusMm, 0, 10000, dw, true);
    l.rateHz = Field(d, "rate_hz", l.rateHz, 1, 1e7, dw);
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
/// One HDF5 identifier, closed by its own close function when the handle goes (RAII); an
/// identifier < 0 (a failed create or open) is held but never closed.
class H5Handle {
public:
  H5Handle(hid_t id, herr_t (*close)(hid_t)) : Id_(id), Close_(close) {}
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  ~H5Handle() { Close(); }
  hid_t Get() const { return Id_; }
  bool Valid() const { return Id_ >= 0; }
  /// Closes now; false when the close failed (for a file: its data did not reach the disk).
  bool Close() {
    const hid_t id = Id_;
    Id_ = -1;
    return id < 0 || Close_(id) >= 0;
  }

private:
  hid_t Id_;
  herr_t (*Close_)(hid_t);
};

void WriteStringAttribute(hid_t obj, const char* name, const std::string& value) {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.Get(), std::max<size_t>(1, value.size()));
  H5Tset_strpad(type.Get(), H5T_STR_NULLPAD);
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Handle attr(H5Acreate2(obj, name, type.Get(), space.Get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.Valid() || H5Awrite(attr.Get(), type.Get(), value.data()) < 0)
    throw std::runtime_error(std::string("HDF5: cannot write attribute ") + name);
}

std::string ReadStringAttribute(hid_t obj, const char* name) {
  H5Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  if (!attr.Valid())
    throw std::runtime_error(std::string("HDF5: no attribute ") + name);
  H5Handle type(H5Aget_type(attr.Get()), H5Tclose);
  const size_t n = H5Tget_size(type.Get());
  std::string s(n, '\0');
  H5Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(mem.Get(), n);
  H5Tset_strpad(mem.Get(), H5T_STR_NULLPAD);
  if (H5Aread(attr.Get(), mem.Get(), s.data()) < 0)
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
  try {
    H5Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!file.Valid())
      throw std::runtime_error("HDF5: cannot create '" + tmp + "'");
    const auto& cols = FrameRecord::Columns();
    std::vector<double> data;
    data.reserve(r.frames.size() * cols.size());
    for (const auto& f : r.frames) {
      const auto row = f.ToRow();
      data.insert(data.end(), row.begin(), row.end());
    }
    hsize_t dims[2] = {hsize_t(r.frames.size()), hsize_t(cols.size())};
    {
      H5Handle space(H5Screate_simple(2, dims, nullptr), H5Sclose);
      H5Handle ds(H5Dcreate2(file.Get(), "frames", H5T_IEEE_F64LE, space.Get(), H5P_DEFAULT,
                             H5P_DEFAULT, H5P_DEFAULT),
                  H5Dclose);
      if (!ds.Valid() || (!data.empty() && H5Dwrite(ds.Get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL,
                                                    H5P_DEFAULT, data.data()) < 0))
        throw std::runtime_error("HDF5: cannot write /frames to '" + tmp + "'");
      std::string names;
      for (size_t i = 0; i < cols.size(); ++i)
        names += (i ? "," : "") + cols[i];
      WriteStringAttribute(ds.Get(), "columns", names);
    }
    WriteStringAttribute(file.Get(), "meta", r.meta.dump());
    if (!file.Close())
      throw std::runtime_error("HDF5: cannot close '" + tmp + "'");
  } catch (...) {
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

namespace {
// One line (without its '\n') of at most kMaxRecordingLineBytes; false at the end of the file.
bool ReadLine(std::istream& in, std::string& line, const std::string& path, int64_t lineNo) {
  line.clear();
  std::streambuf* buf = in.rdbuf();
  for (;;) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof())
      return !line.empty();
    if (c == '\n')
      return true;
    if (line.size() >= kMaxRecordingLineBytes)
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": line longer than " +
                               std::to_string(kMaxRecordingLineBytes) + " bytes");
    line += char(c);
  }
}
} // namespace

Recording ReadRecording(const std::string& path, int64_t maxFrames) {
  if (maxFrames < 1 || maxFrames > kMaxRecordingFrames)
    throw std::invalid_argument("ReadRecording: frame cap " + std::to_string(maxFrames) +
                                " is outside [1, " + std::to_string(kMaxRecordingFrames) + "]");
  {
    std::error_code ec;
    const auto st = std::filesystem::status(path, ec);
    const std::string why = NotARegularFile(path);
    if (!ec && std::filesystem::exists(st) && !why.empty())
      throw std::runtime_error("recording '" + path + "' is not a regular file (it is " + why +
                               "); refused");
  }
  Recording rec;
  const size_t ncols = FrameRecord::Columns().size();
  if (IsHdf5Path(path)) {
#ifdef BM_SESSION_HDF5
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.Valid())
      throw std::runtime_error("cannot open HDF5 recording '" + path + "'");
    rec.meta = ParseJson(ReadStringAttribute(file.Get(), "meta"),
                         "the header of recording '" + path + "'");
    // /frames must be this file's own data: a link to another file, external storage (raw data
    // in other files) or a virtual dataset would make the replay read whatever file they name.
    {
      H5L_info_t link{};
      if (H5Lexists(file.Get(), "frames", H5P_DEFAULT) <= 0 ||
          H5Lget_info(file.Get(), "frames", &link, H5P_DEFAULT) < 0)
        throw std::runtime_error("'" + path + "' has no /frames dataset");
      if (link.type != H5L_TYPE_HARD)
        throw std::runtime_error("'" + path +
                                 "': /frames is a link (to another file or place), not the "
                                 "file's own dataset; refused");
    }
    H5Handle ds(H5Dopen2(file.Get(), "frames", H5P_DEFAULT), H5Dclose);
    if (!ds.Valid())
      throw std::runtime_error("'" + path + "' has no /frames dataset");
    {
      H5Handle dcpl(H5Dget_create_plist(ds.Get()), H5Pclose);
      if (!dcpl.Valid())
        throw std::runtime_error("'" + path + "': cannot read how /frames is stored");
      if (H5Pget_external_count(dcpl.Get()) != 0)
        throw std::runtime_error("'" + path +
                                 "': /frames keeps its data in external files (HDF5 external "
                                 "storage); only data inside the recording are read");
      const H5D_layout_t layout = H5Pget_layout(dcpl.Get());
      if (layout != H5D_CONTIGUOUS && layout != H5D_CHUNKED && layout != H5D_COMPACT)
        throw std::runtime_error("'" + path +
                                 "': /frames is not stored in the file itself (a virtual "
                                 "dataset); refused");
    }
    hsize_t dims[2] = {0, 0};
    const int nd = [&] {
      H5Handle space(H5Dget_space(ds.Get()), H5Sclose);
      return H5Sget_simple_extent_dims(space.Get(), dims, nullptr);
    }();
    if (nd != 2 || dims[1] != ncols)
      throw std::runtime_error("'" + path + "': /frames has the wrong shape");
    if (dims[0] > hsize_t(maxFrames))
      throw std::runtime_error("'" + path + "' declares " + std::to_string(dims[0]) +
                               " frames; at most " + std::to_string(maxFrames) +
                               " are read (one hour at 1 kHz is " +
                               std::to_string(kMaxRecordingFrames) + ")");
    std::vector<double> data(size_t(dims[0] * dims[1]));
    if (!data.empty() &&
        H5Dread(ds.Get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
      throw std::runtime_error("'" + path + "': cannot read /frames");
    for (size_t i = 0; i < dims[0]; ++i) {
      try {
        rec.frames.push_back(FrameRecord::FromRow(
            std::vector<double>(data.begin() + i * ncols, data.begin() + (i + 1) * ncols)));
      } catch (const std::invalid_argument& e) {
        throw std::runtime_error("'" + path + "': frame " + std::to_string(i) + ": " + e.what());
      }
    }
    return rec;
#else
    throw std::runtime_error("cannot read '" + path + "': this build has no HDF5 (BM_WITH_HDF5)");
#endif
  }
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error("cannot read recording '" + path + "'");
  std::string line;
  int64_t lineNo = 0;
  while (ReadLine(in, line, path, lineNo + 1)) {
    ++lineNo;
    if (line.rfind("# bmsession ", 0) == 0) {
      rec.meta =
          ParseJson(std::string_view(line).substr(12),
                    "the header of recording '" + path + "' (line " + std::to_string(lineNo) + ")");
      continue;
    }
    if (line.empty() || line[0] == '#' || line.rfind("frame,", 0) == 0)
      continue;
    const std::vector<double> row = ParseCsvNumbers(line, path + ":" + std::to_string(lineNo));
    if (row.size() != ncols)
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": wrong column count");
    if (int64_t(rec.frames.size()) >= maxFrames)
      throw std::runtime_error("'" + path + "' holds more than " + std::to_string(maxFrames) +
                               " frames; at most " + std::to_string(maxFrames) +
                               " are read (one hour at 1 kHz is " +
                               std::to_string(kMaxRecordingFrames) + ")");
    try {
      rec.frames.push_back(FrameRecord::FromRow(row));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": " + e.what());
    }
  }
  if (rec.meta.is_null())
    throw std::runtime_error("'" + path + "' is not a session recording (no '# bmsession' line)");
  return rec;
}

} // namespace bm
