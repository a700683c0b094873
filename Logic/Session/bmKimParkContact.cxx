#include "bmKimParkContact.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bm {

namespace {
constexpr size_t kAhead = 8; // points fetched ahead of the one read (prefetch distance)
} // namespace

KimParkContact::KimParkContact(const ToolDistanceField& sdf, BoneSurfaceShell& shell,
                               double stiffnessPerArea)
    : Sdf_(sdf), Shell_(shell), KA_(stiffnessPerArea) {}

void KimParkContact::ToolBox(const Eigen::Matrix3d& R, const Eigen::Vector3d& p,
                             Eigen::Vector3d& lo, Eigen::Vector3d& hi, ToolPart part) const {
  Eigen::Vector3d tlo, thi;
  Sdf_.PartBox(part, tlo, thi);
  const Eigen::Vector3d c = 0.5 * (tlo + thi), e = 0.5 * (thi - tlo);
  const Eigen::Vector3d wc = R * c + p;
  const Eigen::Vector3d we = R.cwiseAbs() * e;
  lo = wc - we;
  hi = wc + we;
}

void KimParkContact::SetDepthCap(double capMm, double sliverFraction) {
  Cap_ = capMm > 0 ? capMm : std::numeric_limits<double>::infinity();
  Sliver_ = std::clamp(sliverFraction, 1e-6, 1.0);
  SetCandidateRadius(Radius_);
}

void KimParkContact::SetCandidateRadius(double radiusMm) {
  Radius_ = radiusMm > 0 ? radiusMm : 0.0;
  HaveCandidates_ = false;
  LiveCandidates_ = 0;
  for (CandidateSet& set : Spare_)
    set = CandidateSet{};
  Candidates_.clear();
  Keys_.clear();
  Deep_.clear();
  Groups_.clear();
}

bool KimParkContact::Covers(const Eigen::Matrix3d& R, const Eigen::Vector3d& p) const {
  if (!HaveCandidates_ || R != CandidateR_)
    return false;
  const Eigen::Vector3d d = p - CandidateP_;
  return d.norm() <= Radius_ && (R.transpose() * d).norm() <= Radius_;
}

void KimParkContact::SwapSet(CandidateSet& s) const {
  Candidates_.swap(s.candidates);
  Keys_.swap(s.keys);
  Deep_.swap(s.deep);
  AnchorIds_.swap(s.anchorIds);
  Anchors_.swap(s.anchors);
  Groups_.swap(s.groups);
  std::swap(HaveCandidates_, s.have);
  std::swap(CandidateGeneration_, s.generation);
  std::swap(CandidateR_, s.R);
  std::swap(CandidateP_, s.P);
  std::swap(GatherLo_, s.lo);
  std::swap(GatherHi_, s.hi);
  std::swap(LiveCandidates_, s.live);
  std::swap(LastUse_, s.lastUse);
}

void KimParkContact::SelectSet(const Eigen::Matrix3d& R, const Eigen::Vector3d& p) const {
  LastUse_ = ++UseClock_;
  if (Covers(R, p))
    return;
  CandidateSet* oldest = &Spare_[0];
  for (CandidateSet& s : Spare_) {
    if (s.have && s.R == R) {
      const Eigen::Vector3d d = p - s.P;
      if (d.norm() <= Radius_ && (R.transpose() * d).norm() <= Radius_) {
        SwapSet(s);
        LastUse_ = UseClock_;
        return;
      }
    }
    if (s.lastUse < oldest->lastUse)
      oldest = &s;
  }
  SwapSet(*oldest); // the set in use is kept; the least recently used one is gathered again
  LastUse_ = UseClock_;
  Gather(R, p);
}

void KimParkContact::GatherBrick(int bi, int bj, int bk, const Eigen::Matrix3d& R,
                                 const Eigen::Vector3d& p, uint8_t anchorId,
                                 std::vector<Group>& groups) const {
  const std::vector<int32_t>& bucket = Shell_.Bucket(bi, bj, bk);
  if (bucket.empty())
    return;
  const double rho = Radius_, eps = 1e-9; // eps (mm): far above the rounding of these sums
  const double L = Sdf_.LipschitzBound();
  const Eigen::Matrix3d Rt = R.transpose();
  const Eigen::Vector3d glo = Sdf_.Lo(), ghi = Sdf_.Hi();
  const Eigen::Vector3d grow = Eigen::Vector3d::Constant(rho + eps);
  const Voxmap& bone = Shell_.Bone();
  const int B = Voxmap::kBrick;
  const double half = 0.5 * (B - 1) * bone.Spacing(); // brick centre to its outer voxel centres
  const double ball = std::sqrt(3.0) * half + rho + eps;
  // The brick's points at any covered pose lie within `ball` of its centre's image.
  const auto cw =
      bone.GridToWorld({bi * B + 0.5 * (B - 1), bj * B + 0.5 * (B - 1), bk * B + 0.5 * (B - 1)});
  const Eigen::Vector3d qc = Rt * (Eigen::Vector3d(cw[0], cw[1], cw[2]) - p);
  if (((qc.array() + ball) < glo.array()).any() || ((qc.array() - ball) > ghi.array()).any())
    return; // wholly outside the grid: no point passes the box test
  if (((qc.array() - ball) >= glo.array()).all() && ((qc.array() + ball) < ghi.array()).all()) {
    if (Sdf_.Value(qc) > L * ball + eps)
      return; // wholly in the grid and clear of the tool
  }
  Group group;
  group.begin = uint32_t(Candidates_.size());
  group.brick = {bi, bj, bk};
  group.anchor = p;
  // The bucket's points lie scattered over the shell's array, and a deep point's fill is read from
  // the voxmap: both are fetched ahead (a gather of a drill's hole, 270 000 points, waited on
  // these loads for most of its 30 ms).
  const Voxmap::Fill* fills = bone.FillData();
  const size_t n = bucket.size();
  for (size_t k = 0; k < n; ++k) {
    if (k + 2 * kAhead < n)
      __builtin_prefetch(&Shell_.Point(bucket[k + 2 * kAhead]));
    if (k + kAhead < n)
      __builtin_prefetch(fills + Shell_.Point(bucket[k + kAhead]).voxel);
    const SurfacePoint& sp = Shell_.Point(bucket[k]);
    const Eigen::Vector3d q = Rt * (sp.position - p);
    if (((q.array() + grow.array()) < glo.array()).any() ||
        ((q.array() - grow.array()) > ghi.array()).any())
      continue; // fails the box test at every covered pose
    double d0 = -std::numeric_limits<double>::infinity(); // outside the grid: no bound
    if (Sdf_.InGrid(q)) {
      d0 = Sdf_.Value(q);
      if (d0 >= L * rho + eps)
        continue; // stays outside the tool at every covered pose
      if (d0 < -Cap_ - L * rho - eps && IsSliver(sp.voxel))
        continue; // a sliver deeper than the cap at every covered pose (the grid's margin is
                  // outside the tool, so the point stays in the grid there)
    }
    Candidates_.push_back({sp.position, sp.normal, sp.material, sp.voxel});
    Keys_.push_back(d0);
    Deep_.push_back(0);
    AnchorIds_.push_back(anchorId);
    group.key = std::min(group.key, d0);
  }
  group.end = uint32_t(Candidates_.size());
  if (group.end > group.begin) {
    groups.push_back(group);
    LiveCandidates_ += group.end - group.begin;
  }
}

void KimParkContact::Gather(const Eigen::Matrix3d& R, const Eigen::Vector3d& p) const {
  ++Scans_;
  Candidates_.clear();
  Keys_.clear();
  Deep_.clear();
  AnchorIds_.clear();
  Groups_.clear();
  LiveCandidates_ = 0;
  Anchors_.assign(1, p);
  CandidateR_ = R;
  CandidateP_ = p;
  CandidateGeneration_ = Shell_.Generation();
  HaveCandidates_ = true;
  const double eps = 1e-9;
  const Eigen::Vector3d grow = Eigen::Vector3d::Constant(Radius_ + eps);
  // Every box a covered query scans lies in the whole tool's box at p grown by rho.
  Eigen::Vector3d lo, hi;
  ToolBox(R, p, lo, hi);
  Shell_.BrickRange(lo - grow, hi + grow, GatherLo_, GatherHi_);
  for (int bk = GatherLo_[2]; bk <= GatherHi_[2]; ++bk)
    for (int bj = GatherLo_[1]; bj <= GatherHi_[1]; ++bj)
      for (int bi = GatherLo_[0]; bi <= GatherHi_[0]; ++bi)
        GatherBrick(bi, bj, bk, R, p, 0, Groups_);
}

void KimParkContact::Refresh() const {
  const uint64_t seen = CandidateGeneration_;
  CandidateGeneration_ = Shell_.Generation();
  // The anchor of the keys gathered again: the gathering position.
  if (Anchors_.size() >= kMaxAnchors) { // re-anchor every key at the gathering position
    ReAnchor(CandidateR_.transpose(), CandidateP_);
  } else {
    Anchors_.push_back(CandidateP_);
  }
  const uint8_t anchorId = uint8_t(Anchors_.size() - 1);
  // Merge, in brick order (k, j, i), the unchanged groups with the changed bricks gathered again.
  auto before = [](const std::array<int, 3>& a, const std::array<int, 3>& b) {
    return std::array<int, 3>{a[2], a[1], a[0]} < std::array<int, 3>{b[2], b[1], b[0]};
  };
  NewGroups_.clear();
  size_t g = 0;
  for (int bk = GatherLo_[2]; bk <= GatherHi_[2]; ++bk)
    for (int bj = GatherLo_[1]; bj <= GatherHi_[1]; ++bj)
      for (int bi = GatherLo_[0]; bi <= GatherHi_[0]; ++bi) {
        if (Shell_.BrickStamp(bi, bj, bk) <= seen)
          continue;
        const std::array<int, 3> brick{bi, bj, bk};
        for (; g < Groups_.size() && before(Groups_[g].brick, brick); ++g)
          NewGroups_.push_back(Groups_[g]);
        if (g < Groups_.size() && Groups_[g].brick == brick) {
          LiveCandidates_ -= Groups_[g].end - Groups_[g].begin; // replaced
          ++g;
        }
        ++RefreshedBricks_;
        GatherBrick(bi, bj, bk, CandidateR_, CandidateP_, anchorId, NewGroups_);
      }
  for (; g < Groups_.size(); ++g)
    NewGroups_.push_back(Groups_[g]);
  Groups_.swap(NewGroups_);
  if (Candidates_.size() > 2 * LiveCandidates_ + 4096)
    Compact();
}

void KimParkContact::ReAnchor(const Eigen::Matrix3d& Rt, const Eigen::Vector3d& p) const {
  // The drop of each anchor's keys, once per anchor (at most kMaxAnchors), not once per key: the
  // same expression, so the same bits, for a few hundred anchors instead of tens of thousands of
  // keys (every key's own product and norm took 4-5 ms every 255 queries on a seated reamer).
  const double L = Sdf_.LipschitzBound(), eps = 1e-9;
  Drops_.resize(Anchors_.size());
  for (size_t k = 0; k < Anchors_.size(); ++k)
    Drops_[k] = L * (Rt * (p - Anchors_[k])).norm() + eps;
  for (size_t i = 0; i < Keys_.size(); ++i)
    Keys_[i] += Deep_[i] ? Drops_[AnchorIds_[i]] : -Drops_[AnchorIds_[i]];
  std::fill(AnchorIds_.begin(), AnchorIds_.end(), uint8_t(0));
  Anchors_.assign(1, p);
}

void KimParkContact::Compact() const {
  // Into the spare arrays: a group gathered again sits after the groups that follow it in brick
  // order. The spare arrays keep their capacity from one compaction to the next, and get room for
  // the growth until the next one, so a reaming session stops allocating: fresh arrays at each
  // compaction were grown again by push_back, each growth copying the candidates into new pages
  // (1-5 ms frames every 60-250 ms on a seated reamer, most of it page faults).
  const size_t room = 2 * LiveCandidates_ + 8192;
  SpareCandidates_.clear();
  SpareKeys_.clear();
  SpareDeep_.clear();
  SpareAnchorIds_.clear();
  SpareCandidates_.reserve(room);
  SpareKeys_.reserve(room);
  SpareDeep_.reserve(room);
  SpareAnchorIds_.reserve(room);
  for (Group& grp : Groups_) {
    const uint32_t at = uint32_t(SpareCandidates_.size());
    SpareCandidates_.insert(SpareCandidates_.end(), Candidates_.begin() + grp.begin,
                            Candidates_.begin() + grp.end);
    SpareKeys_.insert(SpareKeys_.end(), Keys_.begin() + grp.begin, Keys_.begin() + grp.end);
    SpareDeep_.insert(SpareDeep_.end(), Deep_.begin() + grp.begin, Deep_.begin() + grp.end);
    SpareAnchorIds_.insert(SpareAnchorIds_.end(), AnchorIds_.begin() + grp.begin,
                           AnchorIds_.begin() + grp.end);
    grp.end = at + (grp.end - grp.begin);
    grp.begin = at;
  }
  Candidates_.swap(SpareCandidates_);
  Keys_.swap(SpareKeys_);
  Deep_.swap(SpareDeep_);
  AnchorIds_.swap(SpareAnchorIds_);
  if (Candidates_.capacity() < room) { // the arrays in use get the same room
    Candidates_.reserve(room);
    Keys_.reserve(room);
    Deep_.reserve(room);
    AnchorIds_.reserve(room);
  }
}

ContactResult KimParkContact::Query(const Eigen::Matrix3d& R, const Eigen::Vector3d& p,
                                    double deadBandMm, ToolPart part, double rimBandMm) const {
  ContactResult out;
  Eigen::Vector3d lo, hi;
  ToolBox(R, p, lo, hi, part);
  const double h = Shell_.Bone().Spacing();
  const double kPoint = KA_ * h * h;
  const Eigen::Matrix3d Rt = R.transpose();
  Eigen::Vector3d nsum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d jacobianT = Eigen::Matrix3d::Zero(); // sum k_i N_i grad d_i^T, grad in T
  const double unknown = -std::numeric_limits<double>::infinity();
  // Adds the point's push; returns its distance (mm) where the field interpolated it, else -inf.
  auto visit = [&](const Eigen::Vector3d& position, const Eigen::Vector3d& normal, float material,
                   int64_t voxel) {
    const Eigen::Vector3d q = Rt * (position - p);
    if (!InField(q))
      return unknown;
    Eigen::Vector3d g;
    const double d = Sdf_.Sample(q, g);
    if (!Pushes(q, d, voxel, deadBandMm, part, rimBandMm))
      return d == Sdf_.Far() ? unknown : d;
    const double pen = -d - deadBandMm;
    const double k = kPoint * material;
    out.force += k * pen * normal;
    jacobianT += (k * normal) * g.transpose();
    nsum += pen * normal;
    out.maxDepthMm = std::max(out.maxDepthMm, pen);
    ++out.points;
    return d;
  };
  if (Radius_ > 0 && deadBandMm >= 0) {
    SelectSet(R, p);
    if (Shell_.Generation() != CandidateGeneration_)
      Refresh();
    // A candidate's key is a lower bound of its distance with the tool at its anchor (one of the
    // last kMaxAnchors query positions), so the key less L times the tool's move since then
    // bounds the distance now; a group's key bounds its candidates' at the group's anchor. A point
    // (or a whole group) whose bound is at least -deadBandMm cannot push (pen <= 0) and is not
    // sampled; a sampled point's key becomes its distance, anchored here. The groups of the
    // bricks a full scan of this box would visit are read in its order.
    const double L = Sdf_.LipschitzBound(), eps = 1e-9;
    const double skipFrom = -deadBandMm + eps;
    if (Anchors_.size() >= kMaxAnchors) { // re-anchor every key here (their bounds now)
      ReAnchor(Rt, p);
    } else if (p != Anchors_.back()) {
      Anchors_.push_back(p);
    }
    const uint8_t here = uint8_t(Anchors_.size() - 1);
    Drops_.resize(Anchors_.size());
    for (size_t k = 0; k < Anchors_.size(); ++k)
      Drops_[k] = L * (Rt * (p - Anchors_[k])).norm() + eps;
    std::array<int, 3> blo{}, bhi{};
    Shell_.BrickRange(lo, hi, blo, bhi);
    const Voxmap::Fill* fills = Shell_.Bone().FillData();
    for (Group& grp : Groups_) {
      if (grp.brick[0] < blo[0] || grp.brick[0] > bhi[0] || grp.brick[1] < blo[1] ||
          grp.brick[1] > bhi[1] || grp.brick[2] < blo[2] || grp.brick[2] > bhi[2])
        continue;
      const double groupDrop = L * (Rt * (p - grp.anchor)).norm() + eps;
      const double none = -std::numeric_limits<double>::infinity();
      if (grp.key - groupDrop >= skipFrom &&
          (grp.deepKey == none || grp.deepKey + groupDrop < -Cap_))
        continue;
      double key = std::numeric_limits<double>::infinity();
      double deepKey = -std::numeric_limits<double>::infinity();
      for (uint32_t i = grp.begin; i < grp.end; ++i) {
        if (i + kAhead < grp.end) // a deep point's fill: read from the voxmap, fetched ahead
          __builtin_prefetch(fills + Candidates_[i + kAhead].voxel);
        const double drop = Drops_[AnchorIds_[i]];
        if (Deep_[i]) {
          if (const double upper = Keys_[i] + drop; upper < -Cap_) {
            deepKey = std::max(deepKey, upper);
            continue;
          }
        } else if (const double lower = Keys_[i] - drop; lower >= skipFrom) {
          key = std::min(key, lower);
          continue;
        }
        const Candidate& c = Candidates_[i];
        const double d = visit(c.position, c.normal, c.material, c.voxel);
        Keys_[i] = d;
        AnchorIds_[i] = here;
        // A deep sliver (-inf, no distance, is never one: it has no bound); fills only fall, so it
        // stays a sliver.
        Deep_[i] = d != none && d < -Cap_ && IsSliver(c.voxel);
        if (Deep_[i])
          deepKey = std::max(deepKey, d);
        else
          key = std::min(key, d);
      }
      grp.key = key;
      grp.deepKey = deepKey;
      grp.anchor = p;
    }
  } else {
    ++Scans_;
    Shell_.ForEachIn(lo, hi, [&](const SurfacePoint& sp) {
      visit(sp.position, sp.normal, sp.material, sp.voxel);
    });
  }
  out.jacobian = jacobianT * Rt; // (R grad)^T = grad^T R^T: R applied once, not per point
  const double n = nsum.norm();
  if (n > 0)
    out.normal = nsum / n;
  return out;
}

bool KimParkContact::Touches(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double deadBandMm,
                             ToolPart part, double rimBandMm) const {
  Eigen::Vector3d lo, hi;
  ToolBox(R, p, lo, hi, part);
  const Eigen::Matrix3d Rt = R.transpose();
  std::array<int, 3> blo{}, bhi{};
  Shell_.BrickRange(lo, hi, blo, bhi);
  // Query's test of each point (Pushes), stopping at the first that pushes.
  for (int bk = blo[2]; bk <= bhi[2]; ++bk)
    for (int bj = blo[1]; bj <= bhi[1]; ++bj)
      for (int bi = blo[0]; bi <= bhi[0]; ++bi)
        for (int32_t slot : Shell_.Bucket(bi, bj, bk)) {
          const SurfacePoint& sp = Shell_.Point(slot);
          const Eigen::Vector3d q = Rt * (sp.position - p);
          if (!InField(q))
            continue;
          Eigen::Vector3d g;
          if (Pushes(q, Sdf_.Sample(q, g), sp.voxel, deadBandMm, part, rimBandMm))
            return true;
        }
  return false;
}

int64_t KimParkContact::Cut(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double depthMm,
                            int64_t& removedFill) {
  Eigen::Vector3d lo, hi;
  ToolBox(R, p, lo, hi);
  const Eigen::Matrix3d Rt = R.transpose();
  return Shell_.Cut(
      lo, hi,
      [&](const Eigen::Vector3d& x) {
        Eigen::Vector3d g;
        return Sdf_.Sample(Rt * (x - p), g) < -depthMm;
      },
      removedFill);
}

} // namespace bm
