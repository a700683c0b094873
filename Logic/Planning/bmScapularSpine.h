// bmScapularSpine.h - the root of the scapular spine on the medial border: the anatomical
// trigonum, found in the scapula's own frame so that the patient's position in the scanner (a
// tilt, the arms raised and the scapula turned with them) does not move it (Docs/Planning.md,
// "Landmarks").
//
// On the scapula's voxels farther than exclusionRadiusMm from the glenoid centre (the vault, the
// neck and the face left out):
//  1. the blade's mid-plane: a weighted least-squares plane refitted three times to the voxels
//     within max(3 mm, 2.5 x their median distance) of it, so a ridge standing off the blade does
//     not tilt it; the blade's half thickness is the 95th percentile of their distances;
//  2. the spine: the voxels more than that half thickness plus max(3 mm, 2 voxels) off the plane,
//     on the side that holds more of them (posterior); its axis, the principal direction of their
//     projections on the plane, turned away from the glenoid;
//  3. the root: from their centroid along the axis, the last point where the blade holds bone
//     (within its thickness of the plane) before a gap of more than 5 mm: the medial border.
// No spine (less than minSpineVolumeMm3 off the blade, or shorter than minSpineLengthMm along its
// axis) gives no root and the reason; DetectLandmarks then finds the trigonum on the axial plane.
//
// Units: mm, mm^3.
#pragma once

#include "bmSegmentedBone.h"
#include "bmVec3.h"

#include <optional>
#include <string>

namespace bm {

struct SpineRootOptions {
  double exclusionRadiusMm = 35;   ///< voxels nearer the glenoid centre are left out, mm
  double minSpineVolumeMm3 = 1000; ///< less bone off the blade is not a spine, mm^3
  double minSpineLengthMm = 20;    ///< a shorter ridge along its axis is not a spine, mm
};

struct SpineRoot {
  Vec3 trigonum{};    ///< the root: on the blade's mid-plane at the medial border, world mm
  Vec3 bladeNormal{}; ///< the blade's mid-plane normal, toward the spine (posterior), unit
  Vec3 axis{};        ///< the spine's axis in the blade's plane, medial, unit
  double bladeHalfThicknessMm = 0;
  double spineVolumeMm3 = 0;
  double spineLengthMm = 0; ///< the ridge's extent along its axis, mm
};

struct SpineRootResult {
  std::optional<SpineRoot> root;
  std::string reason; ///< why there is none ("" when found)
};

/// The root of the spine of bone `label` (the scapula) of `bone`, the glenoid centre `centre`
/// (world mm). See the file comment.
SpineRootResult FindSpineRoot(const SegmentedBone& bone, int label, const Vec3& centre,
                              const SpineRootOptions& options = {});

} // namespace bm
