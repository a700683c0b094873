// bmJoinedHeadCut.h - a humeral head joined to its glenoid at the bone threshold (no joint space
// resolved: thick slices, a narrow joint) cut off along its own sphere, so that landmark
// detection sees two bones facing each other (Docs/Planning.md, "Landmarks").
//
// A humeral head is close to a sphere (radius 12-40 mm, as detection accepts) and the glenoid's
// face is shallower than it (a larger radius of curvature), so the joint, resolved or not, lies
// just outside the head's sphere. On each of the largest bones whose deepest voxel lies at least
// minHeadDepthMm below its surface (the head's inscribed ball; a scapula's vault and blade are
// thinner), deepest first:
//  1. the head's sphere: from the deepest voxel (centre) and its depth (radius), a least-squares
//     sphere (bmGlenoidGeometry.h FitSphere) refitted to the bone's surface points within
//     max(2 voxels, 20 % of the radius) of it whose outward normal is within 35 deg of the
//     sphere's (the head's free surface; the glenoid's face looks the other way);
//  2. accepted when its radius is 12-40 mm, its RMS at most 10 % of the radius plus half the
//     scan's spacing (as detection's head), and points within max(half a voxel, a quarter of the
//     scan's spacing) of it lie in at least minCoverage of the directions from its centre and
//     fill at least minFill of the cap those directions imply (a head is a cap of a sphere; a
//     block's faces and a cylinder's side meet a sphere in rings);
//  3. the socket: a least-squares sphere on the bone's surface points between R + h and R + 12 mm
//     from the head's centre whose outward normal is within 35 deg of the way to it (the face
//     where the joint is resolved) covering at least 3 % of the head's 45-deg cap, kept when
//     it is shallower than the head (radius > R + 1 mm) and holds the head's centre;
//  4. the cut (bmExcludedHead.h): the voxels whose f lies in (0, 2h] (h the voxel): with the
//     socket, the middle of the joint space, the bone the partial volume bridged across it split
//     between the two; without one (a joint fused all over, so narrower than the scan resolves),
//     the two voxels outside the head's sphere. Only within the cone of the joint seen from the
//     head's centre (the socket's points around their mean direction, 15 deg wider; without a
//     socket, 60 deg around the way to the rest of the bone): outside it the shell would cut the
//     head from its own neck, whose stump would face the head as a socket does. f changes by at
//     most the shell's thickness per 6-connected step, so no path through the joint crosses it:
//     the head and the glenoid are separate bones.
// Candidates are returned deepest bone first: the caller keeps the first on which the glenoid is
// found, and leaves the ball of radius cutRadiusMm out of the step scenes' bone.
//
// Units: mm.
#pragma once

#include "bmExcludedHead.h"
#include "bmGlenoidGeometry.h"
#include "bmGlenoidLandmarks.h"
#include "bmSegmentedBone.h"
#include "bmVec3.h"
#include "bmVoxmap.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace bm {

struct HeadCutOptions {
  double minHeadDepthMm = 8; ///< a bone whose deepest voxel is shallower has no head to cut
  int maxBones = 3;          ///< the largest bones tried
  /// The CT's coarsest spacing, mm (0: the voxmap's): the RMS allowed grows by half of it.
  double scanSpacingMm = 0;
  /// Of 1024 directions from the sphere's centre, the share in which a surface point lies within
  /// max(half a voxel, a quarter of the scan's spacing) of it: at least this (a cap of 60 deg
  /// half-angle; a proximal humerus's head shows about half of its sphere)
  double minCoverage = 0.25;
  /// and those directions fill at least this share of the cap their mean direction implies (the
  /// phantom's heads: 0.9-1.0 as a ball, 0.66-0.70 as a proximal humerus, arm at the side or
  /// raised; a block's faces or a cylinder's side, rings: under 0.45)
  double minFill = 0.6;
};

struct HeadCut {
  Voxmap voxmap;         ///< the bone with the shell emptied
  ExcludedHead head;     ///< the head, its socket (if found) and the shell: what a step leaves out
  double rmsMm = 0;      ///< RMS distance of the head's surface points to its sphere, mm
  double coverage = 0;   ///< HeadSphere::coverage
  double fill = 0;       ///< HeadSphere::fill
  int64_t cutVoxels = 0; ///< voxels emptied
};

/// A bone's head sphere (steps 1-2 above).
struct HeadSphere {
  int label = 0;       ///< the bone (SegmentedBone's label)
  SphereFit fit;       ///< centre, radius and RMS, mm
  double coverage = 0; ///< share of the directions its surface lies on the sphere in
  double fill = 0;     ///< share of the implied cap's directions those are
};

/// The head spheres of the largest bones that pass steps 1-2 with `options`' limits, deepest
/// bone first.
std::vector<HeadSphere> FindHeadSpheres(const SegmentedBone& bone,
                                        const HeadCutOptions& options = {});

/// The candidate cuts of `voxmap` (segmented as `bone`), deepest bone first; empty when no bone
/// has a head's depth and sphere.
std::vector<HeadCut> CutJoinedHeads(const Voxmap& voxmap, const SegmentedBone& bone,
                                    const HeadCutOptions& options = {});

/// The landmarks, and the cut that let them be found, if one was needed.
struct LandmarksOnCut {
  GlenoidLandmarks landmarks;
  std::optional<HeadCut> cut;        ///< set when the glenoid was found only after a cut
  std::optional<SegmentedBone> bone; ///< the cut's bone (with `cut`)
};

/// The plan's detection, both faces: `detect` on `bone` (segmented from `voxmap`); when it finds
/// no glenoid, on each of CutJoinedHeads' cuts in turn until one finds it. Rethrows the first
/// NoGlenoidFound when none does, and at once when its message starts "both shoulders" (two
/// glenoids found: no head is joined).
LandmarksOnCut
DetectCuttingAJoinedHead(const Voxmap& voxmap, const SegmentedBone& bone,
                         const std::function<GlenoidLandmarks(const SegmentedBone&)>& detect,
                         const HeadCutOptions& options = {});

/// The report's line for a cut ("joined: ..."), ending in a newline.
std::string HeadCutSummary(const HeadCut& cut);

} // namespace bm
