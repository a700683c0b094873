// bmHeaderCheckNifti.cxx - the NIfTI-1 header check (.nii/.nii.gz): the binary header in either
// byte order, its sizes, datatype, spacing, rescale, qform against sform, data offset and bytes
// (bmHeaderCheckInternal.h).
#include "bmHeaderCheckInternal.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace bm::headercheck {

namespace {

template <class T> T Get(const unsigned char* p, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap)
    std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

/// NIfTI's two orientations, when both are set, must place the volume alike: readers choose
/// differently between them (ITK takes the sform), so a file whose two disagree has no one
/// geometry. Compared at the volume's 8 corners; tolerance half a voxel, at least 0.5 mm.
void CheckQformMatchesSform(const fs::path& file, const uint64_t dims[3],
                            const std::vector<double>& pixdim, const std::vector<double>& q,
                            const std::vector<double>& s) {
  // nifti1_io's nifti_quatern_to_mat44.
  double b = q[0], c = q[1], d = q[2], a = 1 - (b * b + c * c + d * d);
  if (a < 1e-7) {
    a = 1 / std::sqrt(b * b + c * c + d * d);
    b *= a;
    c *= a;
    d *= a;
    a = 0;
  } else {
    a = std::sqrt(a);
  }
  const double xd = pixdim[1] > 0 ? pixdim[1] : 1, yd = pixdim[2] > 0 ? pixdim[2] : 1;
  const double zd = (pixdim[3] > 0 ? pixdim[3] : 1) * (pixdim[0] < 0 ? -1 : 1);
  const double R[3][3] = {
      {a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)},
      {2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b)},
      {2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b}};
  double worst = 0;
  uint64_t at[3] = {0, 0, 0};
  for (int corner = 0; corner < 8; ++corner) {
    const double ijk[3] = {(corner & 1) ? double(dims[0] - 1) : 0.0,
                           (corner & 2) ? double(dims[1] - 1) : 0.0,
                           (corner & 4) ? double(dims[2] - 1) : 0.0};
    double dist = 0;
    for (int r = 0; r < 3; ++r) {
      const double fromQ =
          R[r][0] * xd * ijk[0] + R[r][1] * yd * ijk[1] + R[r][2] * zd * ijk[2] + q[size_t(3 + r)];
      const double fromS = s[size_t(4 * r)] * ijk[0] + s[size_t(4 * r + 1)] * ijk[1] +
                           s[size_t(4 * r + 2)] * ijk[2] + s[size_t(4 * r + 3)];
      dist += (fromQ - fromS) * (fromQ - fromS);
    }
    dist = std::sqrt(dist);
    if (dist > worst) {
      worst = dist;
      for (int k = 0; k < 3; ++k)
        at[k] = uint64_t(ijk[k]);
    }
  }
  const double tol = std::max(0.5, 0.5 * std::min({xd, yd, std::abs(zd)}));
  if (worst > tol) {
    std::ostringstream m;
    m << Q(file) << ": its qform and sform (both set) place voxel (" << at[0] << ", " << at[1]
      << ", " << at[2] << ") " << worst
      << " mm apart: the file has two different geometries and which one is right is unknown";
    throw std::runtime_error(m.str());
  }
}

} // namespace

VolumeHeader CheckNifti(const fs::path& file, const HeaderLimits& limits) {
  unsigned char hdr[348];
  {
    gzFile gz = gzopen(file.c_str(), "rb"); // reads plain files as they are
    if (!gz)
      throw std::runtime_error("cannot open " + Q(file));
    int n = gzread(gz, hdr, sizeof hdr);
    gzclose(gz);
    if (n != int(sizeof hdr))
      throw std::runtime_error(Q(file) + " is too short for a NIfTI header (348 bytes)");
  }
  bool swap = false;
  int32_t sz = Get<int32_t>(hdr, false);
  if (sz != 348) {
    swap = true;
    sz = Get<int32_t>(hdr, true);
  }
  if (sz != 348)
    throw std::runtime_error(Q(file) + " is not a NIfTI-1 file (its header size is not 348)");
  if (std::memcmp(hdr + 344, "n+1", 4) != 0)
    throw std::runtime_error(Q(file) + " is not a single-file NIfTI-1 image (magic n+1)");
  VolumeHeader h;
  h.format = "NIfTI";
  int16_t dim[8];
  for (int i = 0; i < 8; ++i)
    dim[i] = Get<int16_t>(hdr + 40 + 2 * i, swap);
  if (dim[0] < 1 || dim[0] > 7)
    throw std::runtime_error(Q(file) + ": invalid NIfTI dim[0] " + std::to_string(dim[0]));
  for (int i = 4; i <= dim[0]; ++i)
    if (dim[i] > 1)
      throw std::runtime_error(Q(file) + " is a " + std::to_string(dim[0]) + "-D image (axis " +
                               std::to_string(i) + " has " + std::to_string(dim[i]) +
                               " samples); a CT volume must be 3-D");
  if (dim[0] < 3)
    throw std::runtime_error(Q(file) + " is a " + std::to_string(dim[0]) +
                             "-D image; a CT volume must be 3-D");
  for (int a = 0; a < 3; ++a) {
    if (dim[a + 1] < 1)
      throw std::runtime_error(Q(file) + ": size " + std::to_string(dim[a + 1]) + " along axis " +
                               std::to_string(a) + " is not positive");
    h.dims[a] = uint64_t(dim[a + 1]);
  }
  const int16_t datatype = Get<int16_t>(hdr + 70, swap);
  static const std::map<int, std::pair<int, bool>> types = {
      {2, {1, true}},   {4, {2, true}},   {8, {4, true}},   {16, {4, false}},  {64, {8, false}},
      {256, {1, true}}, {512, {2, true}}, {768, {4, true}}, {1024, {8, true}}, {1280, {8, true}}};
  auto t = types.find(datatype);
  if (t == types.end())
    throw std::runtime_error(Q(file) + ": NIfTI datatype " + std::to_string(datatype) +
                             " is not a scalar type a CT uses");
  h.componentBytes = t->second.first;
  h.integerType = t->second.second;
  CheckMemory(file, h, limits);
  std::vector<double> pixdim;
  for (int i = 0; i < 4; ++i)
    pixdim.push_back(Get<float>(hdr + 76 + 4 * i, swap));
  CheckFinite(file, "pixdim", pixdim, 4);
  CheckSpacing(file, {std::abs(pixdim[1]), std::abs(pixdim[2]), std::abs(pixdim[3])});
  const double voxOffset = Get<float>(hdr + 108, swap);
  const double slope = Get<float>(hdr + 112, swap), inter = Get<float>(hdr + 116, swap);
  if (!std::isfinite(slope) || !std::isfinite(inter))
    throw std::runtime_error(Q(file) + " has a non-finite rescale (scl_slope " +
                             std::to_string(slope) + ", scl_inter " + std::to_string(inter) + ")");
  h.hasRescale = slope != 0 && (slope != 1 || inter != 0);
  const int16_t qcode = Get<int16_t>(hdr + 252, swap), scode = Get<int16_t>(hdr + 254, swap);
  std::vector<double> q, s;
  for (int i = 0; i < 6; ++i)
    q.push_back(Get<float>(hdr + 256 + 4 * i, swap));
  for (int i = 0; i < 12; ++i)
    s.push_back(Get<float>(hdr + 280 + 4 * i, swap));
  if (qcode > 0)
    CheckFinite(file, "qform (orientation and origin)", q, 6);
  if (scode > 0)
    CheckFinite(file, "sform (orientation and origin)", s, 12);
  if (qcode > 0 && scode > 0)
    CheckQformMatchesSform(file, h.dims, pixdim, q, s);
  if (!(voxOffset >= 348) || voxOffset > 1e9)
    throw std::runtime_error(Q(file) + ": NIfTI vox_offset " + std::to_string(voxOffset) +
                             " is not a valid data offset");
  h.dataFile = file;
  const uint64_t need =
      h.dims[0] * h.dims[1] * h.dims[2] * uint64_t(h.componentBytes) * uint64_t(h.components);
  const bool gz = Lower(file.extension().string()) == ".gz";
  if (gz) {
    const uint64_t have = GzipBytes(file, 0, uint64_t(voxOffset) + need);
    if (have < uint64_t(voxOffset) + need)
      throw std::runtime_error(
          Q(file) + " is truncated: its voxels need " + std::to_string(need) +
          " bytes after offset " + std::to_string(uint64_t(voxOffset)) +
          ", it holds (uncompressed) " +
          std::to_string(have > uint64_t(voxOffset) ? have - uint64_t(voxOffset) : 0));
  } else {
    CheckDataBytes(file, file, uint64_t(voxOffset), need, false);
  }
  return h;
}

} // namespace bm::headercheck
