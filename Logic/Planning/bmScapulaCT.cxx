#include "bmScapulaCT.h"

#include "bmAtomicFile.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <stdexcept>

namespace bm {

PhantomCTOptions ScapulaCTDefaults() {
  PhantomCTOptions o;
  o.inPlaneSpacingMm = 0.75;
  o.sliceSpacingMm = 1.0;
  o.marginMm = 5.0;
  o.supersample = 4;
  o.noiseHU = 10.0;
  return o;
}

CTImage MakeScapulaCT(const ScapulaPhantom& ph, const PhantomCTOptions& opt,
                      const Progress& progress) {
  return MakeScapulaCT(std::vector<const ScapulaPhantom*>{&ph}, opt, progress);
}

CTImage MakeScapulaCT(const std::vector<const ScapulaPhantom*>& phantoms,
                      const PhantomCTOptions& opt, const Progress& progress) {
  if (phantoms.empty())
    throw std::invalid_argument("scapula CT: no phantom");
  const Vec3 sp{opt.inPlaneSpacingMm, opt.inPlaneSpacingMm, opt.sliceSpacingMm};
  if (!(sp[0] > 0) || !(sp[2] > 0))
    throw std::invalid_argument("scapula CT: spacing must be > 0 mm");
  if (!(opt.noiseHU >= 0) || !(opt.marginMm >= 0))
    throw std::invalid_argument("scapula CT: noise and margin must be >= 0");
  Vec3 lo, hi;
  phantoms[0]->Bounds(lo, hi);
  for (const ScapulaPhantom* ph : phantoms) {
    Vec3 l, h;
    ph->Bounds(l, h);
    for (size_t a = 0; a < 3; ++a)
      lo[a] = std::min(lo[a], l[a]), hi[a] = std::max(hi[a], h[a]);
  }
  size_t n[3];
  double origin[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] -= opt.marginMm, hi[a] += opt.marginMm;
    n[a] = size_t(std::ceil((hi[a] - lo[a]) / sp[a]));
    origin[a] = lo[a] + 0.5 * sp[a];
  }
  CTImage ct;
  ct.hu = HUImage::New();
  HUImage::RegionType region;
  region.SetSize({{n[0], n[1], n[2]}});
  ct.hu->SetRegions(region);
  const double spacing[3] = {sp[0], sp[1], sp[2]};
  ct.hu->SetSpacing(spacing);
  ct.hu->SetOrigin(origin);
  ct.hu->Allocate();
  float* buf = ct.hu->GetBufferPointer();
  std::mt19937 rng(opt.noiseSeed);
  std::normal_distribution<double> noise(0.0, 1.0);
  const int ss = std::max(1, opt.supersample);
  for (size_t k = 0; k < n[2]; ++k) {
    if (k % 8 == 0)
      progress(double(k) / double(n[2]), "making the scapula phantom");
    for (size_t j = 0; j < n[1]; ++j)
      for (size_t i = 0; i < n[0]; ++i) {
        // The phantoms do not overlap: the densest tissue of any is the voxel's.
        const Vec3 c{origin[0] + double(i) * sp[0], origin[1] + double(j) * sp[1],
                     origin[2] + double(k) * sp[2]};
        double hu = -1e30;
        for (const ScapulaPhantom* ph : phantoms)
          hu = std::max(hu, double(ScapulaVoxelHU(*ph, c, sp, ss)));
        if (opt.noiseHU > 0)
          hu += opt.noiseHU * noise(rng);
        buf[i + n[0] * (j + n[1] * k)] = float(hu);
      }
  }
  ct.source = "phantom:scapula";
  ct.format = "phantom";
  ct.modality = "CT";
  ct.seriesDescription = "BoneMachining scapula phantom";
  const size_t total = n[0] * n[1] * n[2];
  const auto mm = std::minmax_element(buf, buf + total);
  ct.huMin = *mm.first;
  ct.huMax = *mm.second;
  progress(1.0, "making the scapula phantom");
  return ct;
}

void WriteScapulaSeries(const ScapulaPhantom& ph, const std::string& folder,
                        const PhantomCTOptions& ctOptions, DicomWriteOptions dicomOptions,
                        const Progress& progress) {
  CTImage ct = MakeScapulaCT(ph, ctOptions, progress.Range(0, 0.6));
  if (dicomOptions.seriesDescription == DicomWriteOptions().seriesDescription)
    dicomOptions.seriesDescription = "BoneMachining scapula phantom";
  if (dicomOptions.patientName == DicomWriteOptions().patientName)
    dicomOptions.patientName = "BoneMachining^scapula phantom";
  WriteDicomSeries(ct, folder, dicomOptions, progress.Range(0.6, 1));
  WriteFileAtomic((std::filesystem::path(folder) / "truth.json").string(),
                  ScapulaTruthJson(ph).dump(2) + "\n");
}

} // namespace bm
