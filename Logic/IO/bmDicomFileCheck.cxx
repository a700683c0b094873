#include "bmDicomFileCheck.h"

#include <gdcmDicts.h>
#include <gdcmGlobal.h>
#include <gdcmTag.h>
#include <gdcmVR.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>

namespace fs = std::filesystem;

namespace bm {

bool HasDicomMagic(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  char buf[132];
  return in.read(buf, sizeof buf) && std::memcmp(buf + 128, "DICM", 4) == 0;
}

bool MayBeDicom(const fs::path& file) {
  std::string ext = file.extension().string();
  for (auto& ch : ext)
    ch = char(std::tolower((unsigned char)ch));
  if (ext == ".dcm" || ext == ".dicom" || ext == ".ima")
    return true;
  std::ifstream in(file, std::ios::binary);
  unsigned char b[132];
  in.read(reinterpret_cast<char*>(b), sizeof b);
  const size_t got = size_t(in.gcount());
  if (got < 4)
    return true; // too short to tell: the check names it
  if (got == sizeof b && std::memcmp(b + 128, "DICM", 4) == 0)
    return true;
  // A Part 10 preamble is usually zeros (the magic after it may be what is damaged).
  if (got >= 128 && std::all_of(b, b + 128, [](unsigned char c) { return c == 0; }))
    return true;
  const unsigned group = unsigned(b[0]) | unsigned(b[1]) << 8;
  return group == 0x0002 || group == 0x0008 || group == 0x0800 || group == 0x0200;
}

namespace {

constexpr int kMaxDepth = 32;
constexpr uint32_t kUndefined = 0xffffffffu;

std::string TagText(uint32_t group, uint32_t element) {
  char tag[16];
  std::snprintf(tag, sizeof tag, "(%04x,%04x)", unsigned(group), unsigned(element));
  return tag;
}

/// "element (gggg,eeee)", or "the pixel data (7fe0,0010)".
std::string ElementText(uint32_t group, uint32_t element) {
  return group == 0x7fe0 && element == 0x0010 ? "the pixel data (7fe0,0010)"
                                              : "element " + TagText(group, element);
}

/// The element walk over one file (see CheckDicomElements).
class Walker {
public:
  explicit Walker(const fs::path& file) : file_(file), in_(file, std::ios::binary) {
    size_ = fs::file_size(file);
  }

  DicomFileSummary Run() {
    if (size_ < 132)
      throw std::runtime_error("'" + file_.string() + "' is too short (" + std::to_string(size_) +
                               " bytes) to be a DICOM file");
    if (!HasDicomMagic(file_))
      throw std::runtime_error("'" + file_.string() +
                               "' is not a DICOM file: no \"DICM\" at byte 128 (files without the "
                               "DICOM Part 10 preamble, e.g. raw ACR-NEMA, are not read: GDCM "
                               "aborts on damaged ones)");
    uint64_t pos = WalkMeta(132);
    const bool implicit = ts_ == "1.2.840.10008.1.2";
    if (!implicit && ts_ != "1.2.840.10008.1.2.1" && ts_.rfind("1.2.840.10008.1.2.4.", 0) != 0 &&
        ts_ != "1.2.840.10008.1.2.5") {
      summary_.hasPixelData = true; // big endian, deflated or unknown: GDCM's checks
      return summary_;
    }
    WalkDataSet(pos, size_, implicit, 0, false);
    return summary_;
  }

private:
  struct Header {
    uint32_t group = 0, element = 0;
    std::string vr; // explicit VR, or the dictionary's for implicit VR ("" unknown)
    uint64_t headerBytes = 8;
    uint32_t length = 0;
  };

  std::string Cut(bool meta) const {
    return "'" + file_.string() + "' is truncated or corrupt inside " +
           (meta ? "its file meta information" : "its data set");
  }

  /// n bytes at pos, through a window of the file (the walk reads small pieces, mostly forward).
  void Read(uint64_t pos, void* out, size_t n, bool meta) {
    if (pos + n > size_)
      throw std::runtime_error(Cut(meta) + " (it ends at byte " + std::to_string(size_) + ")");
    if (pos < windowAt_ || pos + n > windowAt_ + window_.size()) {
      windowAt_ = pos;
      window_.resize(size_t(std::min<uint64_t>(std::max<size_t>(n, 1 << 16), size_ - pos)));
      in_.clear();
      in_.seekg(std::streamoff(pos));
      in_.read(window_.data(), std::streamsize(window_.size()));
      if (uint64_t(in_.gcount()) != window_.size())
        throw std::runtime_error("cannot read '" + file_.string() + "'");
    }
    std::memcpy(out, window_.data() + (pos - windowAt_), n);
  }
  uint32_t U16(uint64_t pos, bool meta) {
    unsigned char b[2];
    Read(pos, b, 2, meta);
    return uint32_t(b[0]) | uint32_t(b[1]) << 8;
  }
  uint32_t U32(uint64_t pos, bool meta) { return U16(pos, meta) | U16(pos + 2, meta) << 16; }
  std::string Text(uint64_t pos, uint32_t length, bool meta) {
    std::string s(length, '\0');
    Read(pos, s.data(), length, meta);
    s.erase(s.find_last_not_of(std::string(" \0", 2)) + 1);
    return s;
  }

  static bool LongVR(const std::string& vr) {
    static const std::set<std::string> longVR = {"OB", "OW", "OF", "OD", "OL", "OV", "SQ",
                                                 "UT", "UN", "UC", "UR", "SV", "UV"};
    return longVR.count(vr) > 0;
  }

  /// The element header at pos (tag, VR, length), ending at most at `end`.
  Header ReadHeader(uint64_t pos, uint64_t end, bool implicit, bool meta) {
    Header h;
    if (pos + 8 > end)
      throw std::runtime_error(Cut(meta) + " (it ends at byte " + std::to_string(end) +
                               ", inside an element's header)");
    h.group = U16(pos, meta);
    h.element = U16(pos + 2, meta);
    const gdcm::VR dictVR = gdcm::Global::GetInstance()
                                .GetDicts()
                                .GetDictEntry(gdcm::Tag(uint16_t(h.group), uint16_t(h.element)))
                                .GetVR();
    if (implicit || h.group == 0xfffe) {
      h.length = U32(pos + 4, meta);
      if (h.group != 0xfffe && dictVR != gdcm::VR::INVALID && dictVR != gdcm::VR::UN &&
          gdcm::VR::GetVRString(dictVR) && std::strlen(gdcm::VR::GetVRString(dictVR)) == 2)
        h.vr = gdcm::VR::GetVRString(dictVR);
      return h;
    }
    char v[2];
    Read(pos + 4, v, 2, meta);
    h.vr = std::string{v[0], v[1]};
    static const std::set<std::string> vrs = {"AE", "AS", "AT", "CS", "DA", "DS", "DT", "FD", "FL",
                                              "IS", "LO", "LT", "OB", "OD", "OF", "OL", "OV", "OW",
                                              "PN", "SH", "SL", "SQ", "SS", "ST", "SV", "TM", "UC",
                                              "UI", "UL", "UN", "UR", "US", "UT", "UV"};
    if (!vrs.count(h.vr)) { // GDCM asserts on an unknown VR
      if (h.group == 0x7fe0 && h.element == 0x0010)
        throw std::runtime_error(Cut(meta) +
                                 ": the pixel data (7fe0,0010) has no valid VR (OB or "
                                 "OW) at byte " +
                                 std::to_string(pos + 4));
      throw std::runtime_error(Cut(meta) + " (no valid VR at byte " + std::to_string(pos + 4) +
                               ")");
    }
    // GDCM's image reading asserts when an image attribute's VR is not the dictionary's.
    if (!meta && (h.group == 0x0028 || h.group == 0x0020 || h.group == 0x0018)) {
      const gdcm::VR vr = gdcm::VR::GetVRType(h.vr.c_str());
      if (dictVR != gdcm::VR::INVALID && dictVR != gdcm::VR::UN && vr != gdcm::VR::UN &&
          !dictVR.Compatible(vr))
        throw std::runtime_error(Cut(meta) + ": element " + TagText(h.group, h.element) +
                                 " has VR " + h.vr + ", not the " + gdcm::VR::GetVRString(dictVR) +
                                 " the DICOM dictionary gives it");
    }
    if (LongVR(h.vr)) {
      h.headerBytes = 12;
      if (pos + 12 > end)
        throw std::runtime_error(Cut(meta) + " (it ends at byte " + std::to_string(end) +
                                 ", inside an element's header)");
      unsigned char reserved[2];
      Read(pos + 6, reserved, 2, meta);
      if (reserved[0] != 0 || reserved[1] != 0) // GDCM asserts on non-zero reserved bytes
        throw std::runtime_error(Cut(meta) + ": " + ElementText(h.group, h.element) + " (VR " +
                                 h.vr + ") has non-zero reserved bytes at byte " +
                                 std::to_string(pos + 6));
      h.length = U32(pos + 8, meta);
    } else {
      h.length = U16(pos + 6, meta);
    }
    return h;
  }

  uint64_t WalkMeta(uint64_t pos) {
    while (true) {
      if (pos + 8 > size_)
        throw std::runtime_error(Cut(true) + " (it ends at byte " + std::to_string(size_) + ")");
      if (U16(pos, true) != 0x0002)
        break;
      const Header h = ReadHeader(pos, size_, false, true);
      if (h.length == kUndefined)
        throw std::runtime_error(Cut(true) + " (an element of undefined length)");
      const uint64_t value = pos + h.headerBytes;
      if (value + h.length > size_)
        throw std::runtime_error(Cut(true) + ": element " + TagText(h.group, h.element) +
                                 " needs " + std::to_string(h.length) + " bytes at byte " +
                                 std::to_string(value) + ", past the file's end at byte " +
                                 std::to_string(size_));
      if (h.element == 0x0010)
        ts_ =
            Text(value, std::min<uint32_t>(h.length, 256), true); // a UID, padded with NUL or space
      pos = value + h.length;
    }
    if (ts_.empty())
      throw std::runtime_error(Cut(true) + " (no transfer syntax, (0002,0010))");
    return pos;
  }

  /// Checks on an element's value: image attribute sizes, the RecognitionCode, the UIDs kept.
  void CheckValue(const Header& h, uint64_t value) {
    const std::string tag = TagText(h.group, h.element);
    if (h.group == 0x0028) {
      static const std::set<uint32_t> single = {0x0002, 0x0006, 0x0008, 0x0010, 0x0011,
                                                0x0100, 0x0101, 0x0102, 0x0103};
      int unit = 0;
      if (h.vr == "US" || h.vr == "SS")
        unit = 2;
      else if (h.vr == "UL" || h.vr == "SL" || h.vr == "FL" || h.vr == "AT")
        unit = 4;
      else if (h.vr == "FD")
        unit = 8;
      if (unit && h.length % uint32_t(unit) != 0)
        throw std::runtime_error(Cut(false) + ": element " + tag + " (VR " + h.vr + ") is " +
                                 std::to_string(h.length) + " bytes long, not a whole number of " +
                                 std::to_string(unit) + "-byte values");
      if (unit == 2 && single.count(h.element) && h.length != 2)
        throw std::runtime_error(Cut(false) + ": element " + tag + " holds " +
                                 std::to_string(h.length) +
                                 " bytes; the image attribute is a single 2-byte value");
    }
    // GDCM asserts on a RecognitionCode (0008,0010; retired, ACR-NEMA) of other content.
    if (h.group == 0x0008 && h.element == 0x0010) {
      const std::string code = Text(value, std::min<uint32_t>(h.length, 64), false);
      if (code.rfind("ACR-NEMA", 0) != 0 && code.rfind("ACRNEMA", 0) != 0 &&
          code.rfind("MIPS 2.0", 0) != 0)
        throw std::runtime_error(Cut(false) +
                                 ": its RecognitionCode (0008,0010) is not ACR-NEMA's");
    }
  }

  /// Walks a data set from pos: to `end` (a defined-length item, the file), or to its item
  /// delimiter (untilDelimiter). Returns the position after it. At depth 0 it stops at the pixel
  /// data.
  uint64_t WalkDataSet(uint64_t pos, uint64_t end, bool implicit, int depth, bool untilDelimiter) {
    if (depth > kMaxDepth)
      throw std::runtime_error("'" + file_.string() + "' nests sequences more than " +
                               std::to_string(kMaxDepth) + " deep");
    while (true) {
      if (pos == end && !untilDelimiter)
        return pos; // complete (at depth 0: a data set without pixel data, not an image)
      const Header h = ReadHeader(pos, end, implicit, false);
      const std::string tag = TagText(h.group, h.element);
      if (h.group == 0xfffe) {
        if (untilDelimiter && h.element == 0xe00d) {
          if (h.length != 0)
            throw std::runtime_error(Cut(false) + ": the item delimiter at byte " +
                                     std::to_string(pos) + " has a length");
          return pos + 8;
        }
        throw std::runtime_error(Cut(false) + ": an item tag " + tag + " at byte " +
                                 std::to_string(pos) + " stands where an element belongs");
      }
      const bool pixelData = h.group == 0x7fe0 && h.element == 0x0010;
      if (pixelData && !implicit && h.vr != "OB" && h.vr != "OW" && h.vr != "UN")
        throw std::runtime_error(Cut(false) +
                                 ": the pixel data (7fe0,0010) has no valid VR (OB or "
                                 "OW) at byte " +
                                 std::to_string(pos + 4));
      if (pixelData && depth == 0) {
        summary_.hasPixelData = true;
        // Encapsulated (compressed) pixel data: its fragments are walked here, since GDCM
        // asserts on a fragment cut short (gdcmSequenceOfFragments.h); a defined length is
        // decoded by GDCM and checked after parsing.
        if (h.length == kUndefined)
          WalkSequence(pos + h.headerBytes, end, implicit, depth, true, true);
        return pos;
      }
      const uint64_t value = pos + h.headerBytes;
      if (h.length == kUndefined) {
        const bool sequence = h.vr == "SQ" || h.vr == "UN" || (implicit && h.vr.empty());
        if (pixelData || h.vr == "OB" || h.vr == "OW") { // encapsulated: fragments
          pos = WalkSequence(value, end, implicit, depth, true, true);
        } else if (sequence) {
          pos = WalkSequence(value, end, implicit || h.vr == "UN", depth, true, false);
        } else {
          throw std::runtime_error(Cut(false) + ": element " + tag + " (VR " + h.vr + ") at byte " +
                                   std::to_string(pos) +
                                   " has undefined length; only sequences may");
        }
        continue;
      }
      if (value + h.length > end)
        throw std::runtime_error(Cut(false) + ": element " + tag + " needs " +
                                 std::to_string(h.length) + " bytes at byte " +
                                 std::to_string(value) + ", past " +
                                 (end == size_ ? "the file's end" : "the end of its item") +
                                 " at byte " + std::to_string(end));
      if (h.vr == "SQ")
        WalkSequence(value, value + h.length, implicit, depth, false, false);
      else
        CheckValue(h, value);
      if (depth == 0 && h.group == 0x0008 && h.element == 0x0016)
        summary_.sopClassUID = Text(value, std::min<uint32_t>(h.length, 64), false);
      if (depth == 0 && h.group == 0x0020 && h.element == 0x000e)
        summary_.seriesUID = Text(value, std::min<uint32_t>(h.length, 64), false);
      pos = value + h.length;
    }
  }

  /// Walks the items of a sequence (or the fragments of encapsulated pixel data) from pos: to
  /// `end` (defined length) or to the sequence delimiter. Returns the position after it.
  uint64_t WalkSequence(uint64_t pos, uint64_t end, bool implicit, int depth, bool undefined,
                        bool fragments) {
    while (true) {
      if (!undefined && pos == end)
        return pos;
      if (pos + 8 > end)
        throw std::runtime_error(Cut(false) + " (it ends at byte " + std::to_string(end) +
                                 " inside a sequence, before its delimiter)");
      const uint32_t group = U16(pos, false), element = U16(pos + 2, false);
      const uint32_t length = U32(pos + 4, false);
      if (group == 0xfffe && element == 0xe0dd && undefined) {
        if (length != 0)
          throw std::runtime_error(Cut(false) + ": the sequence delimiter at byte " +
                                   std::to_string(pos) + " has a length");
        return pos + 8;
      }
      if (group != 0xfffe || element != 0xe000)
        throw std::runtime_error(Cut(false) + ": " + TagText(group, element) + " at byte " +
                                 std::to_string(pos) + " stands where a sequence item belongs");
      const uint64_t value = pos + 8;
      if (length == kUndefined) {
        if (fragments)
          throw std::runtime_error(Cut(false) + ": a pixel data fragment at byte " +
                                   std::to_string(pos) + " has undefined length");
        pos = WalkDataSet(value, end, implicit, depth + 1, true);
        continue;
      }
      if (value + length > end)
        throw std::runtime_error(Cut(false) + ": the item at byte " + std::to_string(pos) +
                                 " needs " + std::to_string(length) + " bytes, past " +
                                 (end == size_ ? "the file's end" : "the end of its sequence") +
                                 " at byte " + std::to_string(end));
      if (!fragments)
        WalkDataSet(value, value + length, implicit, depth + 1, false);
      pos = value + length;
    }
  }

  const fs::path& file_;
  std::ifstream in_;
  uint64_t size_ = 0;
  std::string window_;
  uint64_t windowAt_ = 0;
  std::string ts_;
  DicomFileSummary summary_;
};

} // namespace

DicomFileSummary CheckDicomElements(const fs::path& file) {
  return Walker(file).Run();
}

} // namespace bm
