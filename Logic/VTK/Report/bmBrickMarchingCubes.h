// bmBrickMarchingCubes.h - marching cubes over one small brick of a voxmap, at a cost that follows
// the surface in the brick rather than the brick's volume.
//
// The bone's surface is the iso-surface (fill fraction `iso`, default 0.5) of the voxmap's fills
// (bmVoxmap.h) sampled at the voxel centres, on the grid padded by one void sample on each side
// (samples -1 and Dims along each axis, voxel index coordinates), so bone touching the grid's faces
// is closed. Cell c (per axis) spans the samples c and c + 1; cells -1 .. Dims - 1 exist.
//
// Extract() makes the triangles of a brick of Cells()^3 cells: it reads the brick's samples plus
// a one-sample halo with Voxmap::LoadFillRow (atomic loads: safe while another thread cuts) and
// classifies the fills against the iso in one vectorised pass (a bit mask per row), returns at once
// when no sample of the brick's cells is on the other side of the iso from the rest (and before
// reading anything when the voxmap's occupancy says the bricks it touches hold no bone), and
// otherwise converts the fills to fractions (for the vertices; a quarter of the bricks a reamer's
// pass re-extracts have no surface and skip it) and classifies each cell with VTK's marching-cubes
// case table (vtkMarchingCubesTriangleCases, the table vtkFlyingEdges3D is built from, triangles
// in the same order and orientation). Each cut edge's vertex is made once per brick, by linear
// interpolation from the edge's lower-index sample (as vtkFlyingEdges3D does, so the same edge
// gives the same point in two bricks). Its normal is the negated, normalized fill gradient, by
// central differences at the edge's two samples interpolated along the edge, exactly as
// vtkFlyingEdges3D computes it: the halo makes the gradients on the brick's faces the same as
// inside, so neighbouring bricks' normals match (no seams); on the padded grid's outer samples the
// difference is one-sided, as flying edges makes it on its volume's boundary (a ghost sample of
// value -s beyond the pad gives that with the same formula). So the bricks of a grid together
// give vtkFlyingEdges3D's surface of the whole padded grid (same triangles; points and normals to
// float rounding), with the points on shared brick faces duplicated.
//
// No VTK pipeline, no heap allocation once the scratch buffers and the output's vectors have
// grown to their largest size. Not thread-safe (scratch buffers): one instance per thread.
//
// Units: points in world mm (the voxmap's frame); normals unit vectors; iso a fill fraction.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "bmVoxmap.h"

namespace bm {

class BrickMarchingCubes {
public:
  /// One brick's triangles.
  struct Mesh {
    std::vector<float> points;      ///< x, y, z per point, world mm
    std::vector<float> normals;     ///< x, y, z per point, unit length (0 where the gradient is)
    std::vector<int32_t> triangles; ///< three indices into points per triangle
    int64_t NumPoints() const { return int64_t(points.size() / 3); }
    int64_t NumTriangles() const { return int64_t(triangles.size() / 3); }
    /// Empties the lists, keeping their memory.
    void Clear() {
      points.clear();
      normals.clear();
      triangles.clear();
    }
  };

  /// cells: the brick's edge in cells (2..62: a row of samples is one 64-bit mask; default the
  /// voxmap's occupancy brick); iso: fill fraction of the surface in (0, 1).
  explicit BrickMarchingCubes(int cells = Voxmap::kBrick, double iso = 0.5);

  /// Replaces `out` with the surface within the cells [firstCell, firstCell + Cells()) on each
  /// axis (voxel index coordinates of the cells' lower samples; cells outside -1 .. Dims - 1 make
  /// nothing). Returns the number of triangles. `bone` may be cut by another thread meanwhile:
  /// the result is then a surface of fills read before or after each change, for the caller to
  /// extract again (see Voxmap::SeenBrickGeneration).
  int64_t Extract(const Voxmap& bone, const std::array<int, 3>& firstCell, Mesh& out);

  /// Asks the memory for the first kSlicesAhead slices of the fills Extract(bone, firstCell, ...)
  /// will read (a hint: no loads, no effect on results); Extract asks for each further slice
  /// kSlicesAhead slices before it reads it. Called one brick ahead, the next brick's first cache
  /// misses overlap this brick's work. Slices, not the whole box: a voxmap of 512^3 fills has
  /// slices 1 MiB apart, so the same row of every slice falls into the same set of the L2 cache
  /// (8 ways on the CPUs we measured); the box's 11 slices asked for at once evicted one another
  /// before they were read, a few slices ahead stay.
  void Prefetch(const Voxmap& bone, const std::array<int, 3>& firstCell) const;

  int Cells() const { return B_; }
  double Iso() const { return Iso_; }

private:
  /// Prefetches the rows of the box's slices [z0, z1) (box coordinates) that lie in the grid;
  /// g0: the box's sample 0 in voxel coordinates.
  void PrefetchSlices(const Voxmap& bone, const std::array<int, 3>& g0, int z0, int z1) const;
  /// Slices of the box asked for ahead of the one being read.
  static constexpr int kSlicesAhead = 3;
  /// Reads the fills of the box of samples [firstCell - 1, firstCell + Cells() + 1] into F_ (void
  /// outside the grid) and classifies them into RowBits_.
  void Load(const Voxmap& bone, const std::array<int, 3>& firstCell);
  /// The samples' values from F_ into S_ (the ghost samples beyond the pad as described above):
  /// only for bricks that have a surface, after the classification said so.
  void Convert(const Voxmap& bone, const std::array<int, 3>& firstCell);
  /// True when a voxmap brick that the cells' samples [lo, hi] (voxel coordinates) touch holds
  /// bone.
  static bool AnyBone(const Voxmap& bone, const std::array<int, 3>& lo,
                      const std::array<int, 3>& hi);

  int B_; ///< cells per axis
  int N_; ///< samples per axis of the box read: cells + 1 + the halo on each side
  double Iso_;
  std::vector<float> S_;                ///< the box's samples, index x + N (y + N z)
  Voxmap::Fill IsoFill_;                ///< fills >= this are >= iso
  std::vector<uint64_t> RowBits_;       ///< per box row: bit x set where sample x >= iso
  std::vector<Voxmap::Fill> F_;         ///< the box's fills as loaded, index as S_
  std::vector<uint8_t> Above_;          ///< per box sample: 1 where >= iso (8 bytes spare)
  std::vector<uint64_t> Mask_;          ///< per row of the cells' samples: bit x set where >= iso
  std::vector<int32_t> EdgeVertex_;     ///< per (box sample, axis): the vertex on its cut edge
  std::vector<float> Points_, Normals_; ///< the brick's vertices as made...
  std::vector<int32_t> Triangles_;      ///< ...and triangles, copied into the mesh at the end
};

} // namespace bm
