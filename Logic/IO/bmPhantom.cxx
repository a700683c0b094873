#include "bmPhantom.h"

#include "bmAnalyticGlenoid.h"

#include <itkSmoothingRecursiveGaussianImageFilter.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

namespace bm {

namespace {

constexpr double kPi = std::numbers::pi;

// Glenoid constants (see the header; the shape is bmAnalyticGlenoid.h's).
constexpr double gA = glenoid::kA, gB = glenoid::kB, gRc = glenoid::kRc, gH = glenoid::kH,
                 gRp = glenoid::kRp, gDp = glenoid::kDp;
constexpr std::array<double, 3> gC{-60.0, 20.0, 40.0}, gN{-1, 0, 0}, gU{0, 0, 1}, gV{0, 1, 0};
constexpr float kCorticalHU = 1500, kCancellousHU = 300, kFluidHU = 0, kSoftHU = 40;
// Block.
constexpr double bHalf = 3.0, bDepth = 4.0;
constexpr float kBlockHU = 1600, kAirHU = -1000;

// Shoulder.
constexpr double sR = 22.0, sGap = 3.5, sT = 16.0, sHalfY = 20.0, sHalfZ = 30.0, sShell = 1.5;
constexpr double sX1 = -(sR + sGap), sX0 = sX1 - sT; // the plate's x range
constexpr float kHeadCancellousHU = 250, kPlateCancellousHU = 300;
constexpr double kShoulderBlurMm = 1.5;

float ShoulderHU(const std::array<double, 3>& p) {
  const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  if (r <= sR)
    return r >= sR - sShell ? kCorticalHU : kHeadCancellousHU;
  if (p[0] >= sX0 && p[0] <= sX1 && std::abs(p[1]) <= sHalfY && std::abs(p[2]) <= sHalfZ) {
    const double depth =
        std::min({p[0] - sX0, sX1 - p[0], sHalfY - std::abs(p[1]), sHalfZ - std::abs(p[2])});
    return depth <= sShell ? kCorticalHU : kPlateCancellousHU;
  }
  return kSoftHU;
}

double Dot(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

using Glenoid = glenoid::Region;

Glenoid ClassifyGlenoid(const std::array<double, 3>& p) {
  const std::array<double, 3> d{p[0] - gC[0], p[1] - gC[1], p[2] - gC[2]};
  return glenoid::Classify(Dot(d, gU), Dot(d, gV), Dot(d, gN));
}

double GlenoidVolume() {
  // Solid under the concave face, minus the pilot hole (closed forms + a periodic quadrature).
  const int n = 20000;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    double t = 2 * kPi * i / n;
    double rho2 =
        (gA * gB) * (gA * gB) /
        ((gB * std::cos(t)) * (gB * std::cos(t)) + (gA * std::sin(t)) * (gA * std::sin(t)));
    sum += gRc * gRc * gRc - std::pow(gRc * gRc - rho2, 1.5);
  }
  double capIntegral = sum * (2 * kPi / n) / 3.0; // integral over the ellipse of sqrt(Rc^2 - r^2)
  double solid = kPi * gA * gB * (gH + gRc) - capIntegral;
  double hole = kPi * gRp * gRp * (gDp + gRc) -
                2 * kPi / 3 * (gRc * gRc * gRc - std::pow(gRc * gRc - gRp * gRp, 1.5));
  return solid - hole;
}

} // namespace

std::vector<std::string> PhantomNames() {
  return {"glenoid", "block", "shoulder"};
}

PhantomInfo GetPhantomInfo(const std::string& name) {
  PhantomInfo info;
  info.name = name;
  if (name == "glenoid") {
    info.centreMm = gC;
    info.axisOut = gN;
    info.boneVolumeMm3 = GlenoidVolume();
    double rim = gRc - std::sqrt(gRc * gRc - gA * gA); // face height at the ends of the long axis
    // local w in [-H, rim] along n = -x; u along z; v along y
    info.boneBounds.lo = {gC[0] - rim, gC[1] - gB, gC[2] - gA};
    info.boneBounds.hi = {gC[0] + gH, gC[1] + gB, gC[2] + gA};
    info.pilotHoleRadiusMm = gRp;
    info.pilotHoleDepthMm = gDp;
  } else if (name == "block") {
    info.centreMm = {0, 0, 0};
    info.axisOut = {0, 0, 1};
    info.boneVolumeMm3 = (2 * bHalf) * (2 * bHalf) * bDepth;
    info.boneBounds.lo = {-bHalf, -bHalf, -bDepth};
    info.boneBounds.hi = {bHalf, bHalf, 0};
  } else if (name == "shoulder") {
    info.centreMm = {sX1, 0, 0};
    info.axisOut = {1, 0, 0};
    info.boneVolumeMm3 = 4.0 / 3.0 * kPi * sR * sR * sR + sT * (2 * sHalfY) * (2 * sHalfZ);
    info.boneBounds.lo = {sX0, -sR, -sHalfZ};
    info.boneBounds.hi = {sR, sR, sHalfZ};
  } else {
    throw std::invalid_argument("unknown phantom '" + name + "' (glenoid, block or shoulder)");
  }
  return info;
}

float PhantomHU(const std::string& name, const std::array<double, 3>& p) {
  if (name == "glenoid") {
    switch (ClassifyGlenoid(p)) {
    case Glenoid::Outside:
      return kSoftHU;
    case Glenoid::Hole:
      return kFluidHU;
    case Glenoid::Cortical:
      return kCorticalHU;
    case Glenoid::Cancellous:
      return kCancellousHU;
    }
  }
  if (name == "block")
    return (std::abs(p[0]) <= bHalf && std::abs(p[1]) <= bHalf && p[2] <= 0 && p[2] >= -bDepth)
               ? kBlockHU
               : kAirHU;
  if (name == "shoulder")
    return ShoulderHU(p);
  throw std::invalid_argument("unknown phantom '" + name + "' (glenoid, block or shoulder)");
}

bool PhantomIsBone(const std::string& name, const std::array<double, 3>& p) {
  if (name == "glenoid") {
    auto c = ClassifyGlenoid(p);
    return c == Glenoid::Cortical || c == Glenoid::Cancellous;
  }
  if (name == "shoulder")
    return ShoulderHU(p) != kSoftHU;
  return PhantomHU(name, p) == kBlockHU;
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
