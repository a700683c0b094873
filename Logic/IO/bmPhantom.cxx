#include "bmPhantom.h"

#include <itkSmoothingRecursiveGaussianImageFilter.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace bm {

namespace {

constexpr float kCorticalHU = 1500, kCancellousHU = 300, kFluidHU = 0, kSoftHU = 40;
constexpr float kBlockHU = 1600, kAirHU = -1000;
constexpr float kHeadCancellousHU = 250;
constexpr double kShoulderBlurMm = 1.5;

} // namespace

float PhantomHU(const std::string& name, const std::array<double, 3>& p) {
  const PhantomTissue t = PhantomTissueAt(name, p);
  if (name == "block")
    return t == PhantomTissue::Cortical ? kBlockHU : kAirHU;
  switch (t) {
  case PhantomTissue::Outside:
    return kSoftHU;
  case PhantomTissue::Fluid:
    return kFluidHU;
  case PhantomTissue::Cortical:
    return kCorticalHU;
  case PhantomTissue::Cancellous:
    return kCancellousHU; // the glenoid's and the shoulder's plate: 300 HU
  case PhantomTissue::HeadCancellous:
    return kHeadCancellousHU;
  }
  return kSoftHU;
}

CTImage MakePhantomCT(const std::string& name, const PhantomCTOptions& opt,
                      const Progress& progress) {
  PhantomInfo info = GetPhantomInfo(name);
  const double sp[3] = {opt.inPlaneSpacingMm, opt.inPlaneSpacingMm, opt.sliceSpacingMm};
  size_t n[3];
  double origin[3];
  for (int a = 0; a < 3; ++a) {
    if (!(sp[a] > 0))
      throw std::invalid_argument("phantom CT spacing must be > 0");
    double lo = info.boneBounds.lo[a] - opt.marginMm, hi = info.boneBounds.hi[a] + opt.marginMm;
    n[a] = size_t(std::ceil((hi - lo) / sp[a]));
    origin[a] = lo + 0.5 * sp[a];
  }
  CTImage ct;
  ct.hu = HUImage::New();
  HUImage::RegionType region;
  region.SetSize({{n[0], n[1], n[2]}});
  ct.hu->SetRegions(region);
  ct.hu->SetSpacing(sp);
  ct.hu->SetOrigin(origin);
  ct.hu->Allocate();
  float* buf = ct.hu->GetBufferPointer();
  const int ss = std::max(1, opt.supersample);
  std::mt19937 rng(opt.noiseSeed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (size_t k = 0; k < n[2]; ++k) {
    if (k % 4 == 0)
      progress(double(k) / n[2], "making the " + name + " phantom");
    for (size_t j = 0; j < n[1]; ++j)
      for (size_t i = 0; i < n[0]; ++i) {
        double centre[3] = {origin[0] + i * sp[0], origin[1] + j * sp[1], origin[2] + k * sp[2]};
        double sum = 0;
        for (int c = 0; c < ss; ++c)
          for (int b = 0; b < ss; ++b)
            for (int a = 0; a < ss; ++a) {
              std::array<double, 3> p{centre[0] + ((a + 0.5) / ss - 0.5) * sp[0],
                                      centre[1] + ((b + 0.5) / ss - 0.5) * sp[1],
                                      centre[2] + ((c + 0.5) / ss - 0.5) * sp[2]};
              sum += PhantomHU(name, p);
            }
        buf[i + n[0] * (j + n[1] * k)] = float(sum / (ss * ss * ss));
      }
  }
  const double blur =
      opt.blurSigmaMm ? *opt.blurSigmaMm : (name == "shoulder" ? kShoulderBlurMm : 0);
  if (blur < 0)
    throw std::invalid_argument("phantom CT blur must be >= 0 mm");
  if (blur > 0) {
    auto smooth = itk::SmoothingRecursiveGaussianImageFilter<HUImage, HUImage>::New();
    smooth->SetInput(ct.hu);
    smooth->SetSigma(blur);
    RunFilter(smooth, Progress(), "blurring the " + name + " phantom");
    ct.hu = smooth->GetOutput();
    ct.hu->DisconnectPipeline();
    buf = ct.hu->GetBufferPointer();
  }
  if (opt.noiseHU > 0)
    for (size_t v = 0; v < n[0] * n[1] * n[2]; ++v)
      buf[v] = float(buf[v] + opt.noiseHU * noise(rng));
  ct.source = "phantom:" + name;
  ct.format = "phantom";
  ct.modality = "CT";
  ct.seriesDescription = "BoneMachining " + name + " phantom";
  ct.numFiles = 0;
  float lo = buf[0], hi = buf[0];
  for (size_t v = 0; v < n[0] * n[1] * n[2]; ++v)
    lo = std::min(lo, buf[v]), hi = std::max(hi, buf[v]);
  ct.huMin = lo;
  ct.huMax = hi;
  progress(1.0, "making the " + name + " phantom");
  return ct;
}

PhantomInfo WritePhantomSeries(const std::string& name, const std::string& folder,
                               const PhantomCTOptions& ctOptions, DicomWriteOptions dicomOptions,
                               const Progress& progress) {
  PhantomInfo info = GetPhantomInfo(name);
  CTImage ct = MakePhantomCT(name, ctOptions, progress.Range(0, 0.6));
  if (dicomOptions.seriesDescription == DicomWriteOptions().seriesDescription)
    dicomOptions.seriesDescription = "BoneMachining " + name + " phantom";
  if (dicomOptions.patientName == DicomWriteOptions().patientName)
    dicomOptions.patientName = "BoneMachining^" + name + " phantom";
  WriteDicomSeries(ct, folder, dicomOptions, progress.Range(0.6, 1));
  return info;
}

} // namespace bm
