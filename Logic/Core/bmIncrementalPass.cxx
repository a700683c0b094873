#include "bmIncrementalPass.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "bmCpuEngine.h"
#include "bmElementResidency.h"
#include "bmMorton.h"

namespace bm {

namespace {

constexpr int kBatch = 64; // elements decoded and transformed at a time

/// Margin (in voxels) for float rounding around a window edge on an axis whose values |g| stay
/// below m: fl(t + b) and fl(g + 0.5f) round by at most an ulp each; 16 ulps, plus the key's own
/// rounding to float.
double RoundingMargin(double m) {
  return 16.0 * std::ldexp(m + 1.0, -23) + std::ldexp(1.0, -23);
}

} // namespace

IncrementalPass::IncrementalPass(const PointShell& shell)
    : Shell_(shell), Lists_(shell.Blocks().size()), ListFrame_(shell.Blocks().size(), 0),
      Keys_(shell.Blocks().size()), Pos_(shell.Size(), -1), Stamp_(shell.Size(), 0) {}

void IncrementalPass::FullPassRan(const FrameGeometry& G) {
  HavePrev_ = true;
  PrevA_ = G.A;
  PrevB_ = G.b;
}

void IncrementalPass::EnsureKeys(size_t bi, const FrameGeometry& G) {
  BlockKeys& K = Keys_[bi];
  if (K.gen == AGen_ + 1)
    return;
  const ShellBlock& blk = Shell_.Blocks()[bi];
  const size_t size = blk.end - blk.begin;
  const uint64_t* codes = Shell_.Codes().data();
  const float* A = G.A.data();
  std::array<std::vector<float>, 3> unsorted;
  for (auto& u : unsorted)
    u.resize(size);
  alignas(64) float x[kBatch], y[kBatch], z[kBatch];
  std::array<float, 3> maxT{0, 0, 0};
  for (uint32_t base = blk.begin; base < blk.end; base += kBatch) {
    const int n = int(std::min<uint32_t>(blk.end - base, kBatch));
    ElementCoordsOf(codes + base, n, x, y, z);
    for (int q = 0; q < n; ++q)
      for (size_t a = 0; a < 3; ++a) {
        // VoxelsOf's sum before "+ b", in its order (no FMA: -ffp-contract=off, -mno-fma).
        const float t = A[3 * a] * x[q] + A[3 * a + 1] * y[q] + A[3 * a + 2] * z[q];
        const double u = double(t) + 0.5; // exact
        unsorted[a][base - blk.begin + uint32_t(q)] = float(u - std::floor(u));
        maxT[a] = std::max(maxT[a], std::abs(t));
      }
  }
  for (size_t a = 0; a < 3; ++a) {
    const std::vector<float>& key = unsorted[a];
    std::vector<uint32_t>& id = K.id[a];
    id.resize(size);
    std::iota(id.begin(), id.end(), 0u);
    std::sort(id.begin(), id.end(), [&](uint32_t p, uint32_t q) { return key[p] < key[q]; });
    K.key[a].resize(size);
    for (size_t k = 0; k < size; ++k) {
      K.key[a][k] = key[id[k]];
      id[k] += blk.begin;
    }
  }
  K.maxAbsT = maxT;
  K.gen = AGen_ + 1;
}

IncrementalPass::Engaged IncrementalPass::Entry(uint32_t e, int64_t idx, int32_t brick,
                                                const float* material) const {
  // The full pass's weight: float delta x float material, widened to double where it is used.
  const float w = Shell_.Deltas()[e] * (material ? material[idx] : 1.0f);
  return {idx, brick, e, w, Shell_.Bins()[e], uint8_t(ElementIsCutting(Shell_.Codes()[e]))};
}

void IncrementalPass::VisitAll(size_t bi, const Frame& f, const Voxmap& bone, bool fresh) {
  const ShellBlock& blk = Shell_.Blocks()[bi];
  const uint64_t* codes = Shell_.Codes().data();
  const Voxmap::Fill* fill = bone.FillData();
  std::vector<Engaged>& list = Lists_[bi];
  for (const Engaged& g : list)
    Pos_[g.e] = -1;
  list.clear();
  alignas(64) float gx[kBatch], gy[kBatch], gz[kBatch];
  alignas(64) int64_t vox[kBatch];
  alignas(64) int32_t brick[kBatch];
  for (uint32_t base = blk.begin; base < blk.end; base += kBatch) {
    const int n = int(std::min<uint32_t>(blk.end - base, kBatch));
    ElementCoordsOf(codes + base, n, gx, gy, gz);
    f.G->VoxelsOf(gx, gy, gz, n, vox, brick);
    for (int q = 0; q < n; ++q) {
      const uint32_t e = base + uint32_t(q);
      const int64_t idx = vox[q];
      const bool stays = PackedResidency::Stays(f.words[e], fresh, idx);
      const bool engaged = idx >= 0 && (stays || fill[idx] > 0);
      f.words[e] = PackedResidency::Word(idx, engaged);
      if (engaged) {
        Pos_[e] = int32_t(list.size());
        list.push_back(Entry(e, idx, brick[q], bone.MaterialData()));
      }
    }
  }
}

void IncrementalPass::Update(uint32_t e, int64_t idx, int32_t brick, bool fresh, const Voxmap& bone,
                             std::vector<Engaged>& list, uint64_t* words) {
  const bool stays = PackedResidency::Stays(words[e], fresh, idx);
  const bool engaged = idx >= 0 && (stays || bone.FillData()[idx] > 0);
  words[e] = PackedResidency::Word(idx, engaged);
  int32_t& p = Pos_[e];
  if (engaged) {
    if (p >= 0) {
      list[size_t(p)] = Entry(e, idx, brick, bone.MaterialData());
    } else {
      p = int32_t(list.size());
      list.push_back(Entry(e, idx, brick, bone.MaterialData()));
    }
  } else if (p >= 0) {
    const Engaged last = list.back();
    list[size_t(p)] = last;
    Pos_[last.e] = p;
    list.pop_back();
    p = -1;
  }
}

void IncrementalPass::VisitWindows(size_t bi, const Frame& f, const Voxmap& bone) {
  const ShellBlock& blk = Shell_.Blocks()[bi];
  const FrameGeometry& G = *f.G;
  Candidates_.clear();
  for (int a = 0; a < 3; ++a) {
    const double bOld = PrevB_[size_t(a)], bNew = G.b[size_t(a)];
    const double db = bNew - bOld; // exact: both floats
    if (db == 0)
      continue; // every g_a is the same float as before
    // The boundary of the voxel steps sits at key == -b (mod 1); from b_old to b_new it sweeps
    // the circular window of width |db| centred at -(b_old + db / 2).
    const BlockKeys& K = Keys_[bi];
    const double m = double(K.maxAbsT[size_t(a)]) + std::max(std::abs(bOld), std::abs(bNew));
    const double half = std::abs(db) / 2 + RoundingMargin(m);
    if (half >= 0.5) { // the window covers every key
      VisitAll(bi, f, bone, true);
      Recomputed_ += blk.end - blk.begin;
      return;
    }
    double centre = -(bOld + db / 2);
    centre -= std::floor(centre);
    const double lo = centre - half, hi = centre + half;
    const float* k0 = K.key[size_t(a)].data();
    const float* k1 = k0 + K.key[size_t(a)].size();
    const uint32_t* id = K.id[size_t(a)].data();
    auto take = [&](const float* from, const float* to) {
      for (const float* k = from; k < to; ++k) {
        const uint32_t e = id[k - k0];
        if (Stamp_[e] != f.frameNo) {
          Stamp_[e] = f.frameNo;
          Candidates_.push_back(e);
        }
      }
    };
    // Keys in [lo, hi] taken circularly (a key that rounded up to 1.0f is taken with the keys
    // near 1, from lower_bound to the end: its true value is within the margin of them).
    auto upTo = [&](double x) { return std::upper_bound(k0, k1, float(x)); };
    auto from = [&](double x) { return std::lower_bound(k0, k1, float(x)); };
    // float(x) rounds by at most 2^-24, inside the margin.
    if (lo < 0) {
      take(k0, upTo(hi));
      take(from(lo + 1), k1);
    } else if (hi >= 1) {
      take(from(lo), k1);
      take(k0, upTo(hi - 1));
    } else {
      take(from(lo), upTo(hi));
    }
  }
  Recomputed_ += int64_t(Candidates_.size());
  const uint64_t* codes = Shell_.Codes().data();
  std::vector<Engaged>& list = Lists_[bi];
  alignas(64) uint64_t c[kBatch];
  alignas(64) float gx[kBatch], gy[kBatch], gz[kBatch];
  alignas(64) int64_t vox[kBatch];
  alignas(64) int32_t brick[kBatch];
  for (size_t base = 0; base < Candidates_.size(); base += kBatch) {
    const int n = int(std::min<size_t>(Candidates_.size() - base, kBatch));
    for (int q = 0; q < n; ++q)
      c[q] = codes[Candidates_[base + size_t(q)]];
    ElementCoordsOf(c, n, gx, gy, gz);
    G.VoxelsOf(gx, gy, gz, n, vox, brick);
    for (int q = 0; q < n; ++q)
      Update(Candidates_[base + size_t(q)], vox[q], brick[q], true, bone, list, f.words);
  }
}

void IncrementalPass::Run(const Frame& f, const Voxmap& bone, const CullingOptions& culling,
                          FramePartial& P) {
  const FrameGeometry& G = *f.G;
  if (G.A != KeysA_) { // the keys of every block are another A's
    ++AGen_;
    KeysA_ = G.A;
  }
  P.Clear();
  const bool cutting = G.cutting, remove = G.remove, envelope = f.envelopeRemoves;
  const std::array<float, 3>* an = Shell_.AreaNormals().data();
  const std::array<double, 2>* radial = Shell_.RadialDirs().data();
  const BinForce* table = f.table;
  RequestList& requests = P.removals[0]; // one thread: one removal part
  int64_t thrust = 0, torque = 0, fx = 0, fy = 0;
  int64_t visited = 0, engagedCount = 0, engagedCutting = 0, requested = 0;
  const auto& blocks = Shell_.Blocks();
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const ShellBlock& blk = blocks[bi];
    if (!BlockVisible(blk, G, bone, culling))
      continue; // its list is dropped: ListFrame_ falls behind
    const bool fresh = f.blockFrame[bi] + 1 == f.frameNo;
    f.blockFrame[bi] = f.frameNo;
    if (fresh && ListFrame_[bi] + 1 == f.frameNo) {
      EnsureKeys(bi, G);
      VisitWindows(bi, f, bone);
    } else {
      VisitAll(bi, f, bone, fresh);
    }
    ListFrame_[bi] = f.frameNo;
    visited += blk.end - blk.begin;
    const std::vector<Engaged>& list = Lists_[bi];
    engagedCount += int64_t(list.size());
    if (remove)
      requests.Reserve(list.size());
    Voxmap::RemovalRequest* w = requests.End();
    // Each engaged element's contribution, as CpuEngine::RunPassTask computes it.
    for (const Engaged& g : list) {
      const uint32_t e = g.e;
      if (remove && (envelope || g.cutting))
        if (const int32_t u = G.RemovalUnits(an[e]); u > 0) {
          // Into the last request when it is this voxel's (the list keeps the elements' order,
          // so runs share voxels; the clamped decrement telescopes), branch-free as in the full
          // pass; RequestList's sentinel makes w[-1] always valid.
          const int32_t same = w[-1].voxel == g.idx;
          const int32_t before = w[-1].units & -same;
          w -= same;
          *w++ = {g.idx, before + u, g.brick};
          requested += u;
        }
      if (cutting && g.cutting) {
        ++engagedCutting;
        const double wt = g.w;
        const BinForce& tb = table[g.bin];
        const double c = radial[e][0], s = radial[e][1];
        thrust += int64_t(wt * tb.fz);
        torque += int64_t(wt * tb.torque);
        fx += int64_t(wt * (tb.fx * c - tb.fy * s));
        fy += int64_t(wt * (tb.fx * s + tb.fy * c));
      }
    }
    if (remove)
      requests.SetEnd(w);
  }
  P.SetSums(thrust, torque, fx, fy, visited, engagedCount, engagedCutting, requested);
  PrevA_ = G.A;
  PrevB_ = G.b;
  HavePrev_ = true;
  ++FramesRun_;
}

} // namespace bm
