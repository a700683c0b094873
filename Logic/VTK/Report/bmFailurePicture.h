// bmFailurePicture.h - the picture of a plan that found no glenoid (bmsim plan's failure report):
// the bone it searched, seen from the patient's front (anterior, LPS -y; superior up), with each
// joint the failure names marked by a numbered yellow sphere, numbered in the message's order
// (the two sides of one joint share a mark: "1, 2"), its number written in front of the bone, so
// that the reader sees which bones were taken for what, and where to place the glenoid.
// Rendering needs an X display (bmSurfaceImage.h).
#pragma once

#include <array>
#include <string>
#include <vector>

namespace bm {

class Voxmap;

/// Writes the PNG (sizePx square, atomically) of `bone` with `marks` (world mm) numbered 1, 2, ...
/// Throws std::runtime_error when the bone holds no surface or the file cannot be written.
void WriteFailurePicture(const std::string& path, const Voxmap& bone,
                         const std::vector<std::array<double, 3>>& marks, int sizePx = 800);

} // namespace bm
