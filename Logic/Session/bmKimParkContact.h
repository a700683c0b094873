// bmKimParkContact.h - Kim, Park & Park's contact model (Docs/Interaction.md section 3): bone
// surface point shell (bmBoneSurfaceShell.h) against the tool's signed distance field
// (bmToolDistanceField.h).
//
// For a tool pose (R, p) every bone point x_i under the tool's box is carried into the tool frame,
// q_i = R^T (x_i - p), and its signed distance d_i read by trilinear interpolation. A point deeper
// than the dead band t (d_i < -t) pushes the tool out along the bone normal N_i:
//   F_c = sum k_i (-d_i - t) N_i,   k_i = k_A h^2 m_i
// (k_A a stiffness per unit area, N/mm^3; h^2 the point's area; m_i its material scale), with
// Jacobian dF_c/dp = sum k_i N_i (R grad d_i)^T, which the proxy's 3x3 solve uses (eq. 4). The dead
// band is 0 for Kim et al.'s method; the cutting model uses about one voxel so that voxels the
// engine is still thinning at the hole's wall do not push.
//
// Candidate points (exact, for speed): a haptic frame queries the contact many times at nearby
// poses (the proxy's sweep sub-steps and equilibrium iterations), each over every bone point under
// the tool's box (tens of thousands for a glenoid reamer), most of them not pushing. With a
// candidate radius rho > 0, a query at (R, p) gathers once the points that can touch the tool at
// any p' within rho of p: those whose distance at p, d_i(p), is below L rho (L: the field's
// Lipschitz bound, ToolDistanceField::LipschitzBound, so d_i(p') >= d_i(p) - L |p' - p| and a point
// with d_i(p) >= L rho never touches, for any dead band >= 0), plus those outside the grid at p but
// within rho of it; bricks whose whole ball (brick plus rho) lies in the grid and, by the centre's
// distance and L, clear of the tool are skipped without reading their points. Later queries with
// the same R (a rotation), within rho of that p, while the shell is unchanged
// (BoneSurfaceShell::Generation), read only the candidates of the bricks a full scan of their box
// would visit, in the shell's order. Each candidate keeps a lower bound of its distance at the
// tool position where it was last sampled (its anchor), each brick's group the least bound at its
// own anchor: a point (or a group) whose bound less L times the tool's move since is at least
// -deadBand cannot push (pen <= 0) and is not sampled. The points that push are the same, in the
// same order, as in a full scan, so the result is bit-identical (TestContactCandidates.cxx).
// A change of the shell (the engine's removal, a Boolean cut) does not drop the candidates: a
// covered query first gathers again only the bricks whose points changed since
// (BoneSurfaceShell::BrickStamp), at the gathering pose, and puts their groups back in brick
// order; the other bricks' candidates and keys still hold. So a reaming frame, which changes a
// few bricks at the tool's face, reads the few hundred points of those bricks instead of every
// point under the tool (RefreshedBricks() counts them).
// Slivers (SetDepthCap, the cutting method's): a point deeper than the cap inside the tool whose
// voxel holds less than sliverFraction of bone (default 5 %) does not push. It is bone the spinning
// tool's envelope swept through and the engine's removal left: each element removes what it sweeps,
// rounded down to whole fill units, so a voxel the tool passes over slowly keeps a sliver and
// stays a surface point. At the drill's 0.02 mm voxels, 440 000 such points lay up to 1.2 mm
// inside it, all under 10 % full beyond one voxel. They pushed 46 kN along the axis, which the
// axial feed balance discards, and every query of the solve read them all. A fuller voxel that
// deep is bone the tool was pushed into (a stiff arm can press a reamer three voxels into the
// side of its cut): it pushes, so nothing tunnels. Fills only fall, so a sliver stays one. With
// candidates, a sliver found deeper than the cap keeps an upper bound of its distance (its key
// plus L times the tool's move since its anchor) and is not sampled while that bound stays below
// the cap; a gather leaves out the slivers deeper than the cap at every covered pose. Same pushes,
// same order, as a full scan (TestContactCandidates.cxx).
// Several candidate sets are kept (kSets, the least recently used replaced): a proxy that moves
// back and forth across the axis by more than rho from frame to frame (a reamer's lateral limit
// cycle between its pilot-hole walls) finds the set gathered where it was a few frames before,
// instead of gathering at every frame.
//
// One thread at a time (the haptic thread): Query keeps the candidates in mutable members.
//
// Units: mm, N, N/mm, N/mm^3.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "bmBoneSurfaceShell.h"
#include "bmToolDistanceField.h"

namespace bm {

struct ContactResult {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();    ///< F_c on the tool, N (world)
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero(); ///< dF_c/dp, N/mm
  int points = 0;                                     ///< points in contact
  double maxDepthMm = 0; ///< deepest penetration beyond the dead band, mm
  Eigen::Vector3d normal =
      Eigen::Vector3d::Zero(); ///< unit sum of the contacting points' normals weighted by depth
};

class KimParkContact {
public:
  /// stiffnessPerArea: k_A, N/mm^3 (default 2000: 1 mm^2 of contact 0.01 mm deep holds 20 N).
  KimParkContact(const ToolDistanceField& sdf, BoneSurfaceShell& shell,
                 double stiffnessPerArea = 2000);
  const ToolDistanceField& Field() const { return Sdf_; }
  BoneSurfaceShell& Shell() { return Shell_; }
  double StiffnessPerArea() const { return KA_; }
  /// World box (mm) covering the tool's field at pose (R, p), or only `part` of it (default: the
  /// whole tool).
  void ToolBox(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, Eigen::Vector3d& lo,
               Eigen::Vector3d& hi, ToolPart part = ToolPart::Whole) const;
  /// Contact of the tool at pose (R, p) with dead band deadBandMm (mm, >= 0, default 0), counting
  /// only the bone points nearest to `part` of the tool's surface (default: the whole tool) and,
  /// for a part, at least rimBandMm (mm, default 0) inside its rim (ToolDistanceField::InPart).
  ContactResult Query(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double deadBandMm = 0,
                      ToolPart part = ToolPart::Whole, double rimBandMm = 0) const;
  /// Whether Query(R, p, deadBandMm, part, rimBandMm).points > 0, exactly (the same per-point
  /// test), found by scanning the bone points under the part's box (mm, as Query) and stopping at
  /// the first point in contact. It neither reads nor gathers the candidates: a sweep sub-step only
  /// asks whether the tool touches, and after breakthrough a drill's tip found tens of thousands of
  /// points in contact, each summed by a full query, with a new candidate gather every two voxels.
  bool Touches(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double deadBandMm = 0,
               ToolPart part = ToolPart::Whole, double rimBandMm = 0) const;
  /// Candidate radius rho (mm, >= 0; 0, the default: every query scans the shell under its box).
  void SetCandidateRadius(double radiusMm);
  /// Depth cap (mm, > 0; default infinity: none) and sliver fraction (of a voxel's bone, in
  /// (0, 1], default 0.05): slivers deeper than the cap inside the tool do not push (see above).
  /// Drops the candidates.
  void SetDepthCap(double capMm, double sliverFraction = 0.05);
  double DepthCap() const { return Cap_; }
  double CandidateRadius() const { return Radius_; }
  /// Shell scans so far: full queries (no candidates) and candidate gathers; for benchmarks.
  int64_t Scans() const { return Scans_; }
  /// Candidates held now (0 without a gather); for benchmarks.
  size_t CandidateCount() const { return LiveCandidates_; }
  /// Bricks gathered again after a change of the shell, so far; for benchmarks.
  int64_t RefreshedBricks() const { return RefreshedBricks_; }
  /// Kim et al.'s Boolean removal: bone voxels whose centre is deeper than depthMm inside the tool
  /// at (R, p) are removed and the shell regenerated. Returns voxels removed; fill units in
  /// removedFill.
  int64_t Cut(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double depthMm,
              int64_t& removedFill);

private:
  struct Candidate {
    Eigen::Vector3d position, normal; // world mm, unit
    float material;
    int64_t voxel; // the point's voxel (its fill tells a sliver)
  };
  /// The candidates of one voxmap brick: [begin, end) of Candidates_; key = the least of the
  /// lower bounds of the candidates not known deeper than the cap, deepKey the greatest of the
  /// upper bounds of those that are (-inf: none), both with the tool at `anchor`.
  struct Group {
    uint32_t begin = 0, end = 0;
    std::array<int, 3> brick{0, 0, 0};
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero(); // tool position its keys hold for, mm
    double key = std::numeric_limits<double>::infinity();
    double deepKey = -std::numeric_limits<double>::infinity();
  };
  /// Whether the candidates hold every point that can touch at (R, p).
  bool Covers(const Eigen::Matrix3d& R, const Eigen::Vector3d& p) const;
  /// A candidate set not in use: what the members below hold for the set in use.
  struct CandidateSet {
    std::vector<Candidate> candidates;
    std::vector<double> keys;
    std::vector<uint8_t> deep;
    std::vector<uint8_t> anchorIds;
    std::vector<Eigen::Vector3d> anchors;
    std::vector<Group> groups;
    bool have = false;
    uint64_t generation = 0;
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d P = Eigen::Vector3d::Zero();
    std::array<int, 3> lo{0, 0, 0}, hi{-1, -1, -1};
    size_t live = 0;
    uint64_t lastUse = 0;
  };
  /// Exchanges the set in use with `s`.
  void SwapSet(CandidateSet& s) const;
  /// Makes a set that covers (R, p) the one in use, gathering one (in place of the least recently
  /// used) when none does.
  void SelectSet(const Eigen::Matrix3d& R, const Eigen::Vector3d& p) const;
  void Gather(const Eigen::Matrix3d& R, const Eigen::Vector3d& p) const;
  /// Appends brick (bi, bj, bk)'s candidates at the gathering pose (R, p), their keys anchored at
  /// anchor `anchorId` (== p), and its group to `groups` when it has any.
  void GatherBrick(int bi, int bj, int bk, const Eigen::Matrix3d& R, const Eigen::Vector3d& p,
                   uint8_t anchorId, std::vector<Group>& groups) const;
  /// After a change of the shell: gathers again the bricks whose points changed (at the gathering
  /// pose) and puts their groups back in brick order. Same candidates as a new Gather there.
  void Refresh() const;
  /// Moves every key to its bound with the tool at p (R^T = Rt) and anchors it there: lower
  /// bounds down, the deep candidates' upper bounds up.
  void ReAnchor(const Eigen::Matrix3d& Rt, const Eigen::Vector3d& p) const;
  /// Drops the candidates of replaced groups from the arrays (keeps the groups' order).
  void Compact() const;

  const ToolDistanceField& Sdf_;
  BoneSurfaceShell& Shell_;
  double KA_;
  double Radius_ = 0;
  double Cap_ = std::numeric_limits<double>::infinity();
  double Sliver_ = 0.05;
  /// Whether the voxel holds less than the sliver fraction of bone.
  bool IsSliver(int64_t voxel) const { return Shell_.Bone().Fraction(voxel) < Sliver_; }
  /// Whether q (tool frame, mm) lies in the distance field's box.
  bool InField(const Eigen::Vector3d& q) const {
    return !(q(0) < Sdf_.Lo()(0) || q(1) < Sdf_.Lo()(1) || q(2) < Sdf_.Lo()(2) ||
             q(0) > Sdf_.Hi()(0) || q(1) > Sdf_.Hi()(1) || q(2) > Sdf_.Hi()(2));
  }
  /// Whether a point at q (tool frame), at distance d (mm) from the tool, of voxel `voxel`
  /// pushes: deeper than the dead band, not a sliver below the depth cap, on the part asked for.
  /// Query and Touches share it, so they agree to the bit.
  bool Pushes(const Eigen::Vector3d& q, double d, int64_t voxel, double deadBandMm, ToolPart part,
              double rimBandMm) const {
    return -d - deadBandMm > 0 && !(d < -Cap_ && IsSliver(voxel)) &&
           Sdf_.InPart(q, part, rimBandMm);
  }
  mutable std::vector<Candidate> Candidates_;
  static constexpr size_t kMaxAnchors = 255;
  /// Per candidate: a lower bound of its distance (mm) with the tool at its anchor (-inf: none),
  /// or, for a candidate found deeper than the cap (Deep_), an upper bound; and the anchor's
  /// index in Anchors_ (tool positions, world mm, of recent queries).
  mutable std::vector<double> Keys_;
  mutable std::vector<uint8_t> Deep_;
  mutable std::vector<uint8_t> AnchorIds_;
  mutable std::vector<Eigen::Vector3d> Anchors_;
  mutable std::vector<double> Drops_; // per anchor: L times the tool's move since, mm
  mutable std::vector<Group> Groups_;
  mutable bool HaveCandidates_ = false;
  mutable uint64_t CandidateGeneration_ = 0;
  mutable Eigen::Matrix3d CandidateR_ = Eigen::Matrix3d::Identity();
  mutable Eigen::Vector3d CandidateP_ = Eigen::Vector3d::Zero(); // where they were gathered, mm
  mutable std::array<int, 3> GatherLo_{0, 0, 0}, GatherHi_{-1, -1, -1}; // bricks gathered
  mutable size_t LiveCandidates_ = 0; // candidates of the current groups (the rest: replaced)
  mutable std::vector<Group> NewGroups_;
  // Compact's destination, swapped with the arrays in use (capacity kept).
  mutable std::vector<Candidate> SpareCandidates_;
  mutable std::vector<double> SpareKeys_;
  mutable std::vector<uint8_t> SpareDeep_;
  mutable std::vector<uint8_t> SpareAnchorIds_;
  mutable int64_t RefreshedBricks_ = 0;
  static constexpr int kSets = 6; // candidate sets kept, the one in use included
  mutable std::array<CandidateSet, kSets - 1> Spare_;
  mutable uint64_t LastUse_ = 0, UseClock_ = 0;
  mutable int64_t Scans_ = 0;
};

} // namespace bm
