// bmInvesaliusReader.h - read the CT of an InVesalius 3 project (.inv3).
//
// An .inv3 file is a gzip-compressed tar archive holding main.plist (an Apple XML property list)
// and the volume as a raw array. The layout is taken from main.plist itself: matrix/filename,
// matrix/dtype (int16, uint16, uint8, int8, float32, float64; little endian), matrix/shape
// (slices, rows, columns: a C-order numpy array, so x varies fastest), spacing (x, y, z mm) and
// modality. The project stores no patient position: the image is placed with origin (0, 0, 0) mm
// at the centre of voxel (0, 0, 0), identity direction. Debian's invesalius-examples package ships
// one: /usr/share/doc/invesalius-examples/examples/Cranium.inv3 (a head CT in HU).
#pragma once

#include "bmCTReader.h"

namespace bm {

/// Read the CT of an InVesalius project. Throws std::runtime_error on a broken archive, a missing
/// or inconsistent main.plist, a non-CT modality (unless allowed) or a volume over the memory
/// limit.
CTImage ReadInvesaliusProject(const std::string& path, const ReadOptions& options = {},
                              const Progress& progress = {});

} // namespace bm
