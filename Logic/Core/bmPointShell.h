// bmPointShell.h - the tool as a point shell (Faieghi et al. section II-B; Docs/CostModel.md).
//
// The tool's solid of revolution is voxelised on its own grid (spacing = the tool's bounding box's
// longest side / resolution); the centres of its surface voxels are the elements, each stored as
// one 64-bit code: Morton code of its grid coordinates plus a cutting-edge flag (bmMorton.h),
// sorted by code. Side arrays hold what the frame needs:
//  - areaNormal: outward normal times the element's share of the surface area (mm^2). A motion d
//    (mm) sweeps max(0, areaNormal . d) mm^3 of material in front of the element: removal by the
//    whole envelope (Docs/Model.md section 5);
//  - for cutting elements, a force bin (its radius r on the edge) and delta (mm): its share of the
//    edge's radial extent. Time-averaged lips (default): every element of the edges' surface of
//    revolution cuts, delta = N_c dr / (elements in its radial bin), so the fully engaged shell
//    sums to exactly N_c times one lip (the midpoint rule over the bins). Instantaneous lips: only
//    elements within one spacing of a lip (at spindle angle 0) cut, delta = dr / (elements of that
//    lip in the bin); the shell then turns with the spindle.
// Elements are grouped in blocks of consecutive codes with bounding boxes and normal bounds, so a
// frame can skip whole blocks that cannot touch bone or do not face the motion.
//
// Units: mm, mm^2; tool frame of bmToolModel.h.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "bmToolModel.h"

namespace bm {

enum class LipMode { TimeAveraged, Instantaneous };

/// Radius (mm), radial width (mm) and edge kind of one force bin.
struct ForceBin {
  double r = 0;  ///< bin centre
  double dr = 0; ///< bin width
  EdgeKind kind = EdgeKind::Lip;
};

struct ShellBlock {
  uint32_t begin = 0, end = 0;       ///< element range [begin, end)
  std::array<float, 3> lo{}, hi{};   ///< tool-frame bounds of the elements' voxels, mm
  std::array<float, 3> nLo{}, nHi{}; ///< bounds of the unit outward normals' components
  bool hasCutting = false;
};

class PointShell {
public:
  static constexpr uint16_t kNoBin = 0xFFFF;

  /// Voxelise `tool` with `resolution` cells along its bounding box's longest side (>= 8).
  /// blockSize: elements per block. Throws std::invalid_argument on a bad resolution.
  static PointShell Build(const ToolModel& tool, int resolution,
                          LipMode mode = LipMode::TimeAveraged, int blockSize = 256);

  int Resolution() const { return Resolution_; }
  LipMode Mode() const { return Mode_; }
  /// Element spacing, mm.
  double Spacing() const { return Spacing_; }
  /// Tool-frame position (mm) of grid cell (0,0,0)'s centre.
  const std::array<double, 3>& Origin() const { return Origin_; }
  size_t Size() const { return Codes_.size(); }
  size_t NumCutting() const { return NumCutting_; }

  const std::vector<uint64_t>& Codes() const { return Codes_; }
  const std::vector<std::array<float, 3>>& AreaNormals() const { return AreaNormal_; }
  const std::vector<uint16_t>& Bins() const { return Bin_; }
  const std::vector<float>& Deltas() const { return Delta_; }
  const std::vector<ForceBin>& ForceBins() const { return ForceBins_; }
  const std::vector<ShellBlock>& Blocks() const { return Blocks_; }
  /// Per element (cos phi, sin phi) of its azimuth: px / rho, py / rho in double with px =
  /// Origin()[0] + Spacing() * i (exactly how a backend would compute it), (1, 0) on the axis.
  const std::vector<std::array<double, 2>>& RadialDirs() const { return RadialDir_; }

  /// Tool-frame position (mm) of element e's centre.
  std::array<double, 3> Position(size_t e) const;
  /// Total surface area (mm^2) the elements stand for.
  double SurfaceArea() const;
  /// Bytes held by the shell.
  size_t MemoryBytes() const;

private:
  int Resolution_ = 0;
  LipMode Mode_ = LipMode::TimeAveraged;
  double Spacing_ = 0;
  std::array<double, 3> Origin_{};
  size_t NumCutting_ = 0;
  std::vector<uint64_t> Codes_;
  std::vector<std::array<float, 3>> AreaNormal_;
  std::vector<uint16_t> Bin_;
  std::vector<float> Delta_;
  std::vector<ForceBin> ForceBins_;
  std::vector<ShellBlock> Blocks_;
  std::vector<std::array<double, 2>> RadialDir_;
};

} // namespace bm
