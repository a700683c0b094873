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

/// True when the file has the DICOM Part 10 preamble ("DICM" at byte 128).
bool HasDicomMagic(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  char buf[132];
  return in.read(buf, sizeof buf) && std::memcmp(buf + 128, "DICM", 4) == 0;
}

/// GDCM asserts (aborts the process) on some damaged files: one without a preamble whose first
/// elements are damaged, one cut inside its file meta information or inside an element of its
/// data set. So require the Part 10 preamble ("DICM" at byte 128) and walk the elements here first
/// (the meta group, then the data set's top-level elements up to the pixel data, in explicit or
/// implicit VR little endian), refusing a file that ends inside an element. The walk stops at an
/// element of undefined length (a sequence), at the pixel data, after the first MiB, and for
/// other transfer syntaxes (big endian, deflated), where GDCM's own checks remain. Returns false
/// when the data set ends, complete, without pixel data (not an image; GDCM is not asked to parse
/// it: it asserts on some such files).
bool CheckDicomElements(const fs::path& file) {
  const uint64_t size = fs::file_size(file);
  if (size < 132)
    throw std::runtime_error("'" + file.string() + "' is too short (" + std::to_string(size) +
                             " bytes) to be a DICOM file");
  if (!HasDicomMagic(file))
    throw std::runtime_error("'" + file.string() +
                             "' is not a DICOM file: no \"DICM\" at byte 128 (files without the "
                             "DICOM Part 10 preamble, e.g. raw ACR-NEMA, are not read: GDCM "
                             "aborts on damaged ones)");
  std::ifstream in(file, std::ios::binary);
  const uint64_t limit = std::min<uint64_t>(size, uint64_t(1) << 20);
  std::string buf(limit, '\0');
  in.read(buf.data(), std::streamsize(limit));
  auto u16 = [&](uint64_t at) {
    return uint32_t(uint8_t(buf[at])) | uint32_t(uint8_t(buf[at + 1])) << 8;
  };
  auto u32 = [&](uint64_t at) { return u16(at) | u16(at + 2) << 16; };
  static const std::set<std::string> longVR = {"OB", "OW", "OF", "OD", "OL", "OV", "SQ",
                                               "UT", "UN", "UC", "UR", "SV", "UV"};
  std::string ts;
  bool meta = true, implicit = false;
  uint64_t pos = 132;
  while (true) {
    std::ostringstream cutText;
    cutText << "'" << file.string() << "' is truncated or corrupt inside "
            << (meta ? "its file meta information" : "its data set");
    const std::string cut = cutText.str();
    if (pos == size && !meta)
      return false; // the data set ends with a complete element (no pixel data)
    if (pos + 8 > size)
      throw std::runtime_error(cut + " (it ends at byte " + std::to_string(size) + ")");
    if (pos + 8 > limit)
      return true; // beyond the part read: GDCM's checks
    const uint32_t group = u16(pos), element = u16(pos + 2);
    if (meta && group != 0x0002) {
      if (ts.empty())
        throw std::runtime_error(cut + " (no transfer syntax, (0002,0010))");
      meta = false;
      implicit = ts == "1.2.840.10008.1.2";
      if (!implicit && ts != "1.2.840.10008.1.2.1" && ts.rfind("1.2.840.10008.1.2.4.", 0) != 0 &&
          ts != "1.2.840.10008.1.2.5")
        return true; // big endian, deflated or unknown: GDCM's checks
      continue;
    }
    if (!meta && ((group == 0x7fe0 && element == 0x0010) || group == 0xfffe)) {
      if (pos + (implicit || group == 0xfffe ? 8 : 12) > size) // GDCM asserts on a cut header
        throw std::runtime_error(cut + " (it ends at byte " + std::to_string(size) +
                                 ", inside an element's header)");
      // GDCM asserts on pixel data whose explicit VR is not one of its own or whose reserved
      // bytes are not zero.
      if (group == 0x7fe0 && !implicit && pos + 12 <= limit) {
        const std::string vr{buf[pos + 4], buf[pos + 5]};
        if (vr != "OB" && vr != "OW" && vr != "UN")
          throw std::runtime_error(cut +
                                   ": the pixel data (7fe0,0010) has no valid VR (OB or "
                                   "OW) at byte " +
                                   std::to_string(pos + 4));
        if (buf[pos + 6] != 0 || buf[pos + 7] != 0)
          throw std::runtime_error(cut +
                                   ": the pixel data (7fe0,0010) has non-zero reserved "
                                   "bytes at byte " +
                                   std::to_string(pos + 6));
      }
      return true; // the pixel data (checked after parsing), or an item: GDCM's checks
    }
    uint64_t header = 8, length = 0;
    if (!meta && implicit) {
      length = u32(pos + 4);
    } else {
      const char v0 = buf[pos + 4], v1 = buf[pos + 5];
      static const std::set<std::string> vrs = {
          "AE", "AS", "AT", "CS", "DA", "DS", "DT", "FD", "FL", "IS", "LO", "LT",
          "OB", "OD", "OF", "OL", "OV", "OW", "PN", "SH", "SL", "SQ", "SS", "ST",
          "SV", "TM", "UC", "UI", "UL", "UN", "UR", "US", "UT", "UV"};
      if (!vrs.count(std::string{v0, v1})) // GDCM asserts on an unknown VR
        throw std::runtime_error(cut + " (no valid VR at byte " + std::to_string(pos + 4) + ")");
      // GDCM's image reading asserts when an image attribute's VR is not the dictionary's.
      if (!meta && (group == 0x0028 || group == 0x0020 || group == 0x0018)) {
        const gdcm::VR dictVR = gdcm::Global::GetInstance()
                                    .GetDicts()
                                    .GetDictEntry(gdcm::Tag(uint16_t(group), uint16_t(element)))
                                    .GetVR();
        const gdcm::VR vr = gdcm::VR::GetVRType(std::string{v0, v1}.c_str());
        if (dictVR != gdcm::VR::INVALID && dictVR != gdcm::VR::UN && vr != gdcm::VR::UN &&
            !dictVR.Compatible(vr)) {
          char tag[16];
          std::snprintf(tag, sizeof tag, "(%04x,%04x)", unsigned(group), unsigned(element));
          throw std::runtime_error(cut + ": element " + tag + " has VR " + std::string{v0, v1} +
                                   ", not the " + gdcm::VR::GetVRString(dictVR) +
                                   " the DICOM dictionary gives it");
        }
      }
      if (longVR.count(std::string{v0, v1})) {
        header = 12;
        if (pos + 12 > size)
          throw std::runtime_error(cut + " (it ends at byte " + std::to_string(size) + ")");
        if (pos + 12 > limit)
          return true;
        if (buf[pos + 6] != 0 || buf[pos + 7] != 0) { // GDCM asserts on non-zero reserved bytes
          char tag[16];
          std::snprintf(tag, sizeof tag, "(%04x,%04x)", unsigned(group), unsigned(element));
          throw std::runtime_error(cut + ": element " + tag + " (VR " + std::string{v0, v1} +
                                   ") has non-zero reserved bytes at byte " +
                                   std::to_string(pos + 6));
        }
        length = u32(pos + 8);
      } else {
        length = u16(pos + 6);
      }
    }
    if (length == 0xffffffffu) {
      if (meta)
        throw std::runtime_error(cut + " (an element of undefined length)");
      return true; // a sequence of undefined length: GDCM's checks
    }
    if (pos + header + length > size) {
      char tag[16];
      std::snprintf(tag, sizeof tag, "(%04x,%04x)", unsigned(group), unsigned(element));
      throw std::runtime_error(cut + ": element " + tag + " needs " + std::to_string(length) +
                               " bytes at byte " + std::to_string(pos + header) +
                               ", past the file's end at byte " + std::to_string(size));
    }
    if (meta && element == 0x0010 && pos + header + length <= limit) {
      ts = buf.substr(pos + header, length); // a UID, padded with NUL or space
      ts.erase(ts.find_last_not_of(std::string(" \0", 2)) + 1);
    }
    // GDCM asserts on a RecognitionCode (0008,0010; retired, ACR-NEMA) of other content.
    if (!meta && group == 0x0008 && element == 0x0010 && pos + header + length <= limit) {
      const std::string code = buf.substr(pos + header, length);
      if (code.rfind("ACR-NEMA", 0) != 0 && code.rfind("ACRNEMA", 0) != 0 &&
          code.rfind("MIPS 2.0", 0) != 0)
        throw std::runtime_error(cut + ": its RecognitionCode (0008,0010) is not ACR-NEMA's");
    }
    pos += header + length;
  }
}

} // namespace bm
