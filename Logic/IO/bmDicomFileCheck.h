// bmDicomFileCheck.h - a DICOM file checked byte by byte before GDCM parses it. GDCM asserts
// (aborts the process) on some damaged files: one without a preamble whose first elements are
// damaged, one cut inside its file meta information or inside an element of its data set, an
// unknown VR, an image attribute of another VR or length, damage after a sequence. The reader
// calls these first so that such a file is refused with a message naming the problem
// (Docs/Reliability.md).
#pragma once

#include <filesystem>
#include <string>

namespace bm {

/// True when the file has the DICOM Part 10 preamble ("DICM" at byte 128).
bool HasDicomMagic(const std::filesystem::path& file);

/// True when the file could be DICOM: it has the preamble, or it begins as a DICOM data set
/// without one would (an element of group 0002 or 0008, as raw ACR-NEMA or a damaged preamble).
/// A text file, a picture, ... are not (a folder's README is skipped, not refused).
bool MayBeDicom(const std::filesystem::path& file);

/// What the element walk found.
struct DicomFileSummary {
  bool hasPixelData = false; ///< the data set reaches its pixel data (7fe0,0010)
  std::string sopClassUID;   ///< SOPClassUID (0008,0016), "" when absent
  std::string seriesUID;     ///< SeriesInstanceUID (0020,000e), "" when absent
};

/// Requires the Part 10 preamble and walks every element of the file meta group and of the data
/// set up to the pixel data, in explicit or implicit VR little endian, through sequences of
/// defined and undefined length and their items (nested at most 32 deep), over the whole file. A
/// file is refused (std::runtime_error naming the file, the element and the byte) when it ends
/// inside an element, an item or a sequence; an element's length runs past its item; a VR is
/// unknown; an attribute of groups 0018, 0020 or 0028 has a VR other than the dictionary's; a
/// binary image attribute (group 0028) has a length that is not a whole number of its values, or
/// a single-valued one (Rows, Columns, Bits Allocated, ...) is not 2 bytes; an element other than a
/// sequence, UN or pixel data has undefined length; an item tag stands where an element belongs; a
/// RecognitionCode (0008,0010) is not ACR-NEMA's. For other transfer syntaxes (big endian,
/// deflated) the walk stops after the meta group: GDCM's own checks remain.
DicomFileSummary CheckDicomElements(const std::filesystem::path& file);

} // namespace bm
