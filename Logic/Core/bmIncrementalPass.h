// bmIncrementalPass.h - the CPU engine's pass (bmCpuEngine.h) for one-thread engines, following
// what changes between frames, with the same results bit for bit as the full pass.
//
// With the tool-grid -> voxmap map's matrix A unchanged (bit for bit), an element's value on axis
// a is g_a = fl(t_a + b_a) with t_a = fl(fl(A_a0 x + A_a1 y) + A_a2 z) fixed per element
// (bmFrameGeometry.h VoxelsOf, no FMA), and its voxel on that axis floor(fl(g_a + 0.5f)) is a
// monotone step function of b_a. From b_old to b_new it can change only where t_a + b_a + 0.5
// crosses an integer: for the elements whose key frac(t_a + 0.5) lies in the circular window
// that the boundary -b_a (mod 1) swept, widened by a margin of float rounding (16 ulps of the
// largest |g|). Each block keeps its elements sorted by key per axis (sorted when first needed
// after A changed), finds each window by binary search, and recomputes with VoxelsOf only the
// elements in a window; every other element keeps its voxel exactly, so it keeps its engagement
// (bmElementResidency.h: engaged stays engaged in the same voxel; not engaged means outside the
// grid or fill 0, and fills only decrease between frames).
//
// Forces and removal units change every frame (the feed changes the force table, the motion the
// swept volume), so each frame still sums over every engaged element, from a compact list per
// block (element, voxel, brick): no Morton decode, transform or fill load. The fixed-point sums
// do not depend on order, nor the removal (a clamped decrement per voxel) on the order of its
// requests, and each engaged element adds exactly the full pass's expressions.
//
// Culling (bmCpuEngine.h rules 1 and 2) is evaluated per block per frame as in the full pass. A
// block visible in this frame and the previous one takes the windows; one visible now but not
// then is visited in full (its residency is not "fresh", as in the full pass); a culled block's
// list is dropped. The residency words and the blocks' frames of last visit are the full pass's
// own (CpuEngine's one buffer), kept exactly as the full pass would leave them, so the engine can
// switch between the two paths at any frame.
//
// Runs when: one engine thread, CullingOptions::incremental, the previous frame ran and A is that
// frame's. Otherwise the engine runs the full pass and this pass starts again from it. Fills
// raised or materials changed in place between frames (a bone loaded into the same voxmap) break
// the premises (fills only decrease; an engaged element's material is read when it enters its
// voxel): call Forget() (CpuEngine::ForgetIncremental) after doing so.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "bmFrameGeometry.h"
#include "bmForceModel.h"
#include "bmPointShell.h"
#include "bmVoxmap.h"

namespace bm {

struct CullingOptions;
struct FramePartial;

class IncrementalPass {
public:
  explicit IncrementalPass(const PointShell& shell);

  /// Whether the frame of geometry G can run here: a previous frame ran (either pass) and its A is
  /// G's, bit for bit.
  bool Accepts(const FrameGeometry& G) const { return HavePrev_ && G.A == PrevA_; }

  /// What one frame reads and writes (the engine's state).
  struct Frame {
    const FrameGeometry* G = nullptr;
    uint32_t frameNo = 0;
    bool envelopeRemoves = true;
    const BinForce* table = nullptr; ///< force table in fixed-point units (when G->cutting)
    uint64_t* words = nullptr;       ///< residency per element (PackedResidency)
    uint32_t* blockFrame = nullptr;  ///< frame of each block's last visit
  };
  /// The frame's pass (Accepts() must hold): counts, fixed-point sums and removal requests (in
  /// removal part 0: one thread) into P, which is cleared first.
  void Run(const Frame& f, const Voxmap& bone, const CullingOptions& culling, FramePartial& P);
  /// Records the frame the full pass ran (its A and b), for the next Accepts().
  void FullPassRan(const FrameGeometry& G);
  /// The next frame runs the full pass (after fills were raised in place).
  void Forget() { HavePrev_ = false; }
  /// Frames this pass has run.
  int64_t FramesRun() const { return FramesRun_; }
  /// Elements whose voxel was recomputed in window blocks, over all frames run.
  int64_t Recomputed() const { return Recomputed_; }

private:
  /// An engaged element with what its contribution reads that does not change while it stays
  /// in its voxel (so the frame's sum reads no voxmap array).
  struct Engaged {
    int64_t idx;     ///< its voxel
    int32_t brick;   ///< its voxel's occupancy brick
    uint32_t e;      ///< element
    float w;         ///< delta (mm) x the voxel's material, as the full pass forms it
    uint16_t bin;    ///< force bin
    uint8_t cutting; ///< ElementIsCutting
  };
  Engaged Entry(uint32_t e, int64_t idx, int32_t brick, const float* material) const;
  void EnsureKeys(size_t bi, const FrameGeometry& G);
  /// Every element of block bi: voxel, residency, list (fresh: visited in the previous frame).
  void VisitAll(size_t bi, const Frame& f, const Voxmap& bone, bool fresh);
  /// The elements in block bi's windows only.
  void VisitWindows(size_t bi, const Frame& f, const Voxmap& bone);
  /// Residency and list update for element e visiting voxel idx (brick) this frame.
  void Update(uint32_t e, int64_t idx, int32_t brick, bool fresh, const Voxmap& bone,
              std::vector<Engaged>& list, uint64_t* words);

  const PointShell& Shell_;
  bool HavePrev_ = false;
  std::array<float, 9> PrevA_{};
  std::array<float, 3> PrevB_{};
  /// A's generation: counts changes of A among the frames run here (the keys' validity).
  uint32_t AGen_ = 0;
  std::array<float, 9> KeysA_{};
  // Per block
  std::vector<std::vector<Engaged>> Lists_;
  std::vector<uint32_t> ListFrame_; ///< frame the list was last made current (0: never)
  /// A block's elements sorted by key per axis, made when the block first takes the windows
  /// under an A (only blocks near bone hold them).
  struct BlockKeys {
    std::array<std::vector<float>, 3> key;   ///< frac(t_a + 0.5), ascending
    std::array<std::vector<uint32_t>, 3> id; ///< the element of each key
    std::array<float, 3> maxAbsT{};          ///< the largest |t_a| of the block's elements
    uint32_t gen = 0;                        ///< AGen_ + 1 of the keys (0: none)
  };
  std::vector<BlockKeys> Keys_;
  // Per element
  std::vector<int32_t> Pos_;    ///< position in its block's list, -1 when not in it
  std::vector<uint32_t> Stamp_; ///< frame it was last recomputed in a window
  std::vector<uint32_t> Candidates_;
  int64_t FramesRun_ = 0, Recomputed_ = 0;
};

} // namespace bm
