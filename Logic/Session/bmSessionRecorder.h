// bmSessionRecorder.h - a session's per-frame record to CSV and to HDF5 (one file per session),
// and reading either back (for bmsim replay).
//
// CSV: a first line "# bmsession {json}" holding the metadata (scene, session options, device
// limits), a header of FrameRecord::Columns(), then one row per frame at 17 significant digits
// (doubles round-trip exactly). HDF5: dataset /frames (frames x columns, double) with attribute
// "columns" (comma-separated names) and attribute "meta" on the root group (the JSON). Both are
// written atomically (temporary file beside the target, then rename).
//
// HDF5 needs a build with libhdf5 (BM_WITH_HDF5 and the library found); without it the HDF5
// functions throw std::runtime_error and HasHdf5() is false.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bmFrameRecord.h"
#include "bmHapticSession.h"

namespace bm {

struct Recording {
  nlohmann::json meta; ///< {"scene": ..., "session": ..., "device": ...}
  std::vector<FrameRecord> frames;
};

/// Most frames a recording may hold (one hour at 1 kHz): a file declaring more is refused before
/// its frames are allocated.
constexpr int64_t kMaxRecordingFrames = 3'600'000;
/// Longest line of a CSV recording accepted (bytes; the header line holds the scene).
constexpr size_t kMaxRecordingLineBytes = size_t(16) << 20;

/// Session options and device limits as JSON (for the metadata) and back. FromJson checks every
/// field it reads: the wrong type, or a value outside its range (e.g. sdf_resolution in [8, 512]
/// cells, rate_hz in [1, 10^7] Hz, max_force_N in (0, 100] N), throws std::runtime_error
/// naming the field and the range.
nlohmann::json SessionOptionsToJson(const SessionOptions& o, const DeviceLimits& limits);
SessionOptions SessionOptionsFromJson(const nlohmann::json& j, DeviceLimits& limits);

bool HasHdf5();
/// Throws std::runtime_error naming the file on failure (nothing is left half written).
void WriteRecordingCsv(const std::string& path, const Recording& r);
/// The CSV form into a stream (for writers that save several files together).
void WriteRecordingCsv(std::ostream& out, const Recording& r);
void WriteRecordingHdf5(const std::string& path, const Recording& r);
/// By extension: .h5/.hdf5 -> HDF5, otherwise CSV.
void WriteRecording(const std::string& path, const Recording& r);
/// Reads a file written by WriteRecording (by extension); throws std::runtime_error naming the
/// file and the problem on bad input: not a regular file (a FIFO would block), a header that is
/// not JSON or nested deeper than kMaxJsonDepth, more than kMaxRecordingFrames frames, a CSV line
/// longer than kMaxRecordingLineBytes, a cell that is not a number, a wrong column count.
/// maxFrames: a lower cap than kMaxRecordingFrames for callers that want one (frames).
Recording ReadRecording(const std::string& path, int64_t maxFrames = kMaxRecordingFrames);

} // namespace bm
