#include "bmBoneSegmenter.h"

#include <itkBinaryThresholdImageFilter.h>
#include <itkRegionOfInterestImageFilter.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace bm {

namespace {

std::string FormatPoint(const std::array<double, 3>& p) {
  std::ostringstream os;
  os << "(" << p[0] << ", " << p[1] << ", " << p[2] << ") mm";
  return os.str();
}

std::string FormatBox(const Box3& b) {
  std::ostringstream os;
  os << "[" << b.lo[0] << ", " << b.hi[0] << "] x [" << b.lo[1] << ", " << b.hi[1] << "] x ["
     << b.lo[2] << ", " << b.hi[2] << "] mm";
  return os.str();
}

} // namespace

CTImage CropCT(const CTImage& ct, const Box3& roi, int margin) {
  const HUImage* img = ct.hu.GetPointer();
  const auto full = img->GetLargestPossibleRegion();
  std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (int c = 0; c < 8; ++c) {
    itk::Point<double, 3> p;
    for (int a = 0; a < 3; ++a)
      p[a] = (c >> a & 1) ? roi.hi[a] : roi.lo[a];
    itk::ContinuousIndex<double, 3> ci;
    img->TransformPhysicalPointToContinuousIndex(p, ci);
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], ci[a]);
      hi[a] = std::max(hi[a], ci[a]);
    }
  }
  HUImage::RegionType region;
  for (int a = 0; a < 3; ++a) {
    long i0 = long(std::floor(lo[a] + 0.5)) - margin, i1 = long(std::ceil(hi[a] - 0.5)) + margin;
    i0 = std::max<long>(i0, full.GetIndex(a));
    i1 = std::min<long>(i1, full.GetIndex(a) + long(full.GetSize(a)) - 1);
    if (i1 < i0)
      throw std::runtime_error("the region of interest " + FormatBox(roi) +
                               " lies outside the CT, whose bounds are " +
                               FormatBox(ct.WorldBounds()));
    region.SetIndex(a, i0);
    region.SetSize(a, size_t(i1 - i0 + 1));
  }
  auto roiFilter = itk::RegionOfInterestImageFilter<HUImage, HUImage>::New();
  roiFilter->SetInput(img);
  roiFilter->SetRegionOfInterest(region);
  RunFilter(roiFilter, Progress(), "cropping");
  CTImage out = ct;
  out.hu = roiFilter->GetOutput();
  out.hu->DisconnectPipeline();
  out.warnings.clear();
  return out;
}

BoneSegmentation SegmentBone(const CTImage& ct, const SegmentationOptions& opt,
                             const Progress& progress) {
  const HUImage* hu = ct.hu.GetPointer();
  const auto region = hu->GetLargestPossibleRegion();
  const int nx = int(region.GetSize(0)), ny = int(region.GetSize(1)), nz = int(region.GetSize(2));
  const int64_t n = int64_t(nx) * ny * nz;
  const auto sp = hu->GetSpacing();
  const double voxelVolume = sp[0] * sp[1] * sp[2];
  const float* H = hu->GetBufferPointer();
  auto idx = [&](int i, int j, int k) {
    return int64_t(i) + int64_t(nx) * (int64_t(j) + int64_t(ny) * k);
  };

  // Seed: inside the image?
  std::array<int, 3> seedIdx{-1, -1, -1};
  if (opt.seedMm) {
    itk::Point<double, 3> p;
    for (int a = 0; a < 3; ++a)
      p[a] = (*opt.seedMm)[a];
    itk::ContinuousIndex<double, 3> ci;
    hu->TransformPhysicalPointToContinuousIndex(p, ci);
    for (int a = 0; a < 3; ++a) {
      double f = std::floor(ci[a] + 0.5) - double(region.GetIndex(a));
      if (!(f >= 0 && f < double(region.GetSize(a))))
        throw std::runtime_error("the seed point " + FormatPoint(*opt.seedMm) +
                                 " lies outside the image, whose bounds are " +
                                 FormatBox(ct.WorldBounds()));
      seedIdx[a] = int(f);
    }
  }

  // Metal (SegmentationOptions::metalHU), when it lies above the bone threshold: a threshold at
  // or above it asks for the dense material itself.
  const float metalHU = std::isfinite(opt.metalHU) && opt.metalHU > opt.thresholdHU
                            ? opt.metalHU
                            : std::numeric_limits<float>::infinity();

  // 1. Threshold.
  auto thr = itk::BinaryThresholdImageFilter<HUImage, MaskImage>::New();
  thr->SetInput(hu);
  thr->SetLowerThreshold(opt.thresholdHU);
  // Metal is not bone (SegmentationOptions::metalHU).
  thr->SetUpperThreshold(std::isfinite(metalHU) ? std::nextafter(metalHU, -1e30f)
                                                : std::numeric_limits<float>::max());
  thr->SetInsideValue(1);
  thr->SetOutsideValue(0);
  RunFilter(thr, progress.Range(0, 0.1), "segmenting bone: threshold");
  MaskImage::Pointer mask = thr->GetOutput();
  mask->DisconnectPipeline();
  uint8_t* M = mask->GetBufferPointer();
  BoneSegmentation seg;
  if (std::isfinite(metalHU)) {
    double sum[3] = {0, 0, 0};
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          if (H[idx(i, j, k)] >= metalHU) {
            ++seg.metalVoxels;
            sum[0] += i, sum[1] += j, sum[2] += k;
          }
    if (seg.metalVoxels > 0) {
      itk::ContinuousIndex<double, 3> ci;
      for (int a = 0; a < 3; ++a)
        ci[a] = double(region.GetIndex(a)) + sum[a] / double(seg.metalVoxels);
      itk::Point<double, 3> at;
      hu->TransformContinuousIndexToPhysicalPoint(ci, at);
      std::ostringstream os;
      os.precision(1);
      os << std::fixed << "metal (an implant or screw?): " << double(seg.metalVoxels) * voxelVolume
         << " mm^3 at or above " << metalHU << " HU, centred at "
         << FormatPoint({at[0], at[1], at[2]}) << ", is not bone and is left out";
      seg.warnings.push_back(os.str());
    }
  }
  if (opt.box)
    MaskOutsideBox(mask, *opt.box);
  // Excluded heads: their bone is not bone, and their voxels are not soft tissue to the
  // partial-volume estimate of the bone beside them.
  std::vector<uint8_t> inHead;
  if (!opt.excludeHeads.empty()) {
    inHead.assign(size_t(n), 0);
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          itk::Index<3> at{
              {region.GetIndex(0) + i, region.GetIndex(1) + j, region.GetIndex(2) + k}};
          itk::Point<double, 3> p;
          hu->TransformIndexToPhysicalPoint(at, p);
          for (const auto& head : opt.excludeHeads)
            if (head.Contains({p[0], p[1], p[2]})) {
              const int64_t v = idx(i, j, k);
              inHead[size_t(v)] = 1;
              seg.headVoxels += M[v] ? 1 : 0;
              M[v] = 0;
              break;
            }
        }
  }
  for (int64_t v = 0; v < n; ++v)
    seg.thresholdVoxels += M[v];
  if (seg.thresholdVoxels == 0 && opt.box)
    throw std::runtime_error("no bone found inside the oriented box: no voxel there reaches the "
                             "bone threshold of " +
                             std::to_string(int(opt.thresholdHU)) + " " + opt.valueUnit);
  if (seg.thresholdVoxels == 0) {
    float mx = -std::numeric_limits<float>::infinity();
    for (int64_t v = 0; v < n; ++v)
      mx = std::max(mx, H[v]);
    std::ostringstream os;
    os << "no bone found: no voxel reaches the bone threshold of " << opt.thresholdHU << " "
       << opt.valueUnit << " (the highest value in the CT is " << mx << " " << opt.valueUnit
       << "); lower the threshold";
    throw std::runtime_error(os.str());
  }

  // 2. Components.
  std::vector<itk::SizeValueType> sizes;
  LabelImage::Pointer labels;
  if (opt.seedMm || !opt.keepAllComponents || !opt.excludeSeedsMm.empty()) {
    labels =
        LabelComponents(mask, true, sizes, progress.Range(0.1, 0.3), "segmenting bone: components");
    seg.numComponents = int(sizes.size());
  } else {
    seg.numComponents = -1; // not counted
  }
  // The bone label at a voxel, else the nearest among its 26 neighbours.
  auto labelNear = [&](const std::array<int, 3>& v) { return NearestLabel(labels, v, 1); };
  if (opt.seedMm || !opt.keepAllComponents) {
    const uint32_t* L = labels->GetBufferPointer();
    uint32_t keep = 1; // largest after relabelling
    if (opt.seedMm) {
      keep = labelNear(seedIdx);
      if (!keep) {
        std::ostringstream os;
        os << "the seed point " << FormatPoint(*opt.seedMm) << " is not on bone: its voxel is "
           << H[idx(seedIdx[0], seedIdx[1], seedIdx[2])] << " " << opt.valueUnit
           << ", below the bone threshold of " << opt.thresholdHU << " " << opt.valueUnit
           << " (place the seed on the bone to keep)";
        throw std::runtime_error(os.str());
      }
    }
    for (int64_t v = 0; v < n; ++v)
      M[v] = L[v] == keep ? 1 : 0;
  }

  // 3. Separate the bones at exclude seeds from the kept bone.
  auto BoneVoxelNear = [&](const std::array<int, 3>& v) -> std::optional<std::array<int, 3>> {
    if (M[idx(v[0], v[1], v[2])])
      return v;
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const std::array<int, 3> w{v[0] + di, v[1] + dj, v[2] + dk};
          if (w[0] >= 0 && w[1] >= 0 && w[2] >= 0 && w[0] < nx && w[1] < ny && w[2] < nz &&
              M[idx(w[0], w[1], w[2])])
            return w;
        }
    return std::nullopt;
  };
  std::vector<std::array<int, 3>> excludeOnKept;
  for (const auto& e : opt.excludeSeedsMm) {
    const auto v = VoxelOfPoint(hu, e);
    if (!v) {
      seg.warnings.push_back("the exclude seed " + FormatPoint(e) +
                             " lies outside the image, whose bounds are " +
                             FormatBox(ct.WorldBounds()) + "; ignored");
      continue;
    }
    const uint32_t l = labelNear(*v);
    if (!l) {
      std::ostringstream os;
      os << "the exclude seed " << FormatPoint(e) << " is not on bone (its voxel is "
         << H[idx((*v)[0], (*v)[1], (*v)[2])] << " " << opt.valueUnit
         << ", below the bone threshold of " << opt.thresholdHU << " " << opt.valueUnit
         << "); ignored";
      seg.warnings.push_back(os.str());
      continue;
    }
    // Its voxel on the kept bone (the seed's voxel, else a bone neighbour); none when the seed
    // is on a bone already dropped.
    if (const auto on = BoneVoxelNear(*v))
      excludeOnKept.push_back(*on);
  }
  labels = nullptr;
  if (!excludeOnKept.empty()) {
    std::optional<std::array<int, 3>> include;
    if (opt.seedMm)
      include = BoneVoxelNear(seedIdx);
    seg.separation =
        SeparateBones(mask, include, excludeOnKept, opt.separation, progress.Range(0.3, 0.45));
  }
  for (int64_t v = 0; v < n; ++v)
    seg.keptVoxels += M[v];

  // 4. Fill cavities.
  CavityFillOptions fillOpt;
  fillOpt.fill = opt.fillHoles;
  fillOpt.closingRadiusVoxels = opt.closingRadiusVoxels;
  fillOpt.maxHoleVolumeMm3 = opt.maxHoleVolumeMm3;
  fillOpt.holeMinMeanHU = opt.holeMinMeanHU;
  fillOpt.holeMaxMeanHU = metalHU;
  // Every bone kept (the plan's joint search): the fill must not join the humeral head to the
  // glenoid across a joint space the closing encloses.
  fillOpt.keepBonesApart = opt.keepAllComponents && !opt.seedMm;
  const CavityFillResult filled = FillCavities(mask, hu, fillOpt, progress.Range(0.45, 0.6));
  seg.holesFilled = filled.holesFilled;
  seg.borderHolesFilled = filled.borderHolesFilled;
  seg.filledVoxels = filled.filledVoxels;
  progress(0.65, "segmenting bone: partial volume");

  // 5. Bone fraction and bone HU. Band = voxels with a 26-neighbour on the other side of the mask.
  seg.fraction = FractionImage::New();
  seg.fraction->SetRegions(region);
  seg.fraction->CopyInformation(hu);
  seg.fraction->Allocate();
  seg.boneHU = HUImage::New();
  seg.boneHU->SetRegions(region);
  seg.boneHU->CopyInformation(hu);
  seg.boneHU->Allocate();
  float* F = seg.fraction->GetBufferPointer();
  float* BH = seg.boneHU->GetBufferPointer();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<uint8_t> band(size_t(n), 0);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        int64_t v = idx(i, j, k);
        bool in = M[v] != 0;
        bool b = false;
        for (int dk = -1; dk <= 1 && !b; ++dk)
          for (int dj = -1; dj <= 1 && !b; ++dj)
            for (int di = -1; di <= 1 && !b; ++di) {
              int ii = i + di, jj = j + dj, kk = k + dk;
              if (ii < 0 || jj < 0 || kk < 0 || ii >= nx || jj >= ny || kk >= nz)
                continue;
              b = (M[idx(ii, jj, kk)] != 0) != in;
            }
        band[size_t(v)] = b;
        F[v] = in ? 1.0f : 0.0f;
        BH[v] = in ? H[v] : nan;
      }
    if (k % 8 == 0)
      progress(0.65 + 0.15 * k / nz, "segmenting bone: partial volume");
  }
  if (opt.partialVolume) {
    for (int k = 0; k < nz; ++k) {
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          int64_t v = idx(i, j, k);
          // A voxel of an excluded head stays empty, however bright.
          if (!band[size_t(v)] || M[v] == 2 || H[v] >= metalHU ||
              (!inHead.empty() && inHead[size_t(v)]))
            continue;
          double softSum = 0, softN = 0, boneMax = -1e30, near3Bone = -1e30, near3Soft = 0,
                 near3SoftN = 0;
          for (int dk = -2; dk <= 2; ++dk)
            for (int dj = -2; dj <= 2; ++dj)
              for (int di = -2; di <= 2; ++di) {
                int ii = i + di, jj = j + dj, kk = k + dk;
                if (ii < 0 || jj < 0 || kk < 0 || ii >= nx || jj >= ny || kk >= nz)
                  continue;
                int64_t w = idx(ii, jj, kk);
                if (w == v)
                  continue;
                bool in = M[w] != 0;
                bool pure = !band[size_t(w)];
                if (pure && in)
                  boneMax = std::max(boneMax, double(H[w]));
                const bool head = !inHead.empty() && inHead[size_t(w)];
                if (pure && !in && H[w] < metalHU && !head)
                  softSum += H[w], softN += 1;
                if (std::abs(di) <= 1 && std::abs(dj) <= 1 && std::abs(dk) <= 1) {
                  if (in)
                    near3Bone = std::max(near3Bone, double(H[w]));
                  else if (H[w] < metalHU && !head)
                    near3Soft += H[w], near3SoftN += 1;
                }
              }
          double bone = boneMax > -1e29 ? boneMax : near3Bone;
          double soft = softN > 0 ? softSum / softN
                                  : (near3SoftN > 0 ? near3Soft / near3SoftN
                                                    : double(opt.thresholdHU) - 200.0);
          if (bone < -1e29)
            bone = std::max<double>(H[v], opt.thresholdHU);
          if (bone - soft < 50.0)
            continue; // no contrast to estimate from: keep the mask's 0/1
          double f = std::clamp((double(H[v]) - soft) / (bone - soft), 0.0, 1.0);
          F[v] = float(f);
          BH[v] = f > 0 ? float(bone) : nan;
        }
      if (k % 8 == 0)
        progress(0.8 + 0.15 * k / nz, "segmenting bone: partial volume");
    }
  }

  // Volume and bounds.
  long double vol = 0;
  int lo[3] = {nx, ny, nz}, hi[3] = {-1, -1, -1};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        float f = F[idx(i, j, k)];
        if (f <= 0)
          continue;
        vol += f;
        lo[0] = std::min(lo[0], i), hi[0] = std::max(hi[0], i);
        lo[1] = std::min(lo[1], j), hi[1] = std::max(hi[1], j);
        lo[2] = std::min(lo[2], k), hi[2] = std::max(hi[2], k);
      }
  seg.boneVolumeMm3 = double(vol) * voxelVolume;
  HUImage::RegionType bb;
  for (int a = 0; a < 3; ++a) {
    bb.SetIndex(a, region.GetIndex(a) + lo[a]);
    bb.SetSize(a, size_t(hi[a] - lo[a] + 1));
  }
  seg.boneBounds = WorldBoxOfRegion(hu, bb);
  progress(1.0, "segmenting bone");
  return seg;
}

} // namespace bm
