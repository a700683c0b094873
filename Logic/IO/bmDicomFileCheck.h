// bmDicomFileCheck.h - a DICOM file checked byte by byte before GDCM parses it. GDCM asserts
// (aborts the process) on some damaged files: one without a preamble whose first elements are
// damaged, one cut inside its file meta information or inside an element of its data set. The
// reader calls these first so that such a file is refused with a message naming the problem
// (Docs/Reliability.md).
#pragma once

#include <filesystem>

namespace bm {

/// True when the file has the DICOM Part 10 preamble ("DICM" at byte 128).
bool HasDicomMagic(const std::filesystem::path& file);

/// Requires the Part 10 preamble and walks the elements (the meta group, then the data set's
/// top-level elements up to the pixel data, in explicit or implicit VR little endian), refusing a
/// file that ends inside an element (std::runtime_error naming the file, the element and the
/// bytes). The walk stops at an element of undefined length (a sequence), at the pixel data, after
/// the first MiB, and for other transfer syntaxes (big endian, deflated), where GDCM's own checks
/// remain. Returns false when the data set ends, complete, without pixel data (not an image).
bool CheckDicomElements(const std::filesystem::path& file);

} // namespace bm
