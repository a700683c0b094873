// Helpers shared by the BMIO tests: scratch folders, phantom series, DICOM tag surgery.
#pragma once

#include "bmPhantom.h"

#include <gdcmItem.h>
#include <gdcmReader.h>
#include <gdcmSequenceOfItems.h>
#include <gdcmWriter.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace bmtest {

namespace fs = std::filesystem;

/// A fresh scratch folder under the system temp dir, removed when the object goes.
struct ScratchDir {
  fs::path path;
  explicit ScratchDir(const std::string& name) {
    path = fs::temp_directory_path() / ("bmio-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  fs::path operator/(const std::string& s) const { return path / s; }
  /// Names of the entries in the folder (to check nothing was left behind).
  std::vector<std::string> Entries() const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(path))
      v.push_back(e.path().filename().string());
    return v;
  }
};

/// Sorted DICOM files of a series folder.
inline std::vector<fs::path> SeriesFiles(const fs::path& dir) {
  std::vector<fs::path> v;
  for (const auto& e : fs::directory_iterator(dir))
    v.push_back(e.path());
  std::sort(v.begin(), v.end());
  return v;
}

/// Rewrite a DICOM file after `edit` changed its data set.
template <class Edit> void EditDicom(const fs::path& file, Edit edit) {
  gdcm::Reader r;
  r.SetFileName(file.c_str());
  if (!r.Read())
    throw std::runtime_error("test: cannot read " + file.string());
  edit(r.GetFile().GetDataSet());
  gdcm::Writer w;
  w.SetFile(r.GetFile());
  w.SetFileName(file.c_str());
  if (!w.Write())
    throw std::runtime_error("test: cannot write " + file.string());
}

/// Replace (or add) a string-valued tag.
inline void SetTag(gdcm::DataSet& ds, uint16_t g, uint16_t e, gdcm::VR vr, std::string value) {
  if (value.size() % 2)
    value.push_back(' ');
  gdcm::DataElement de(gdcm::Tag(g, e));
  de.SetVR(vr);
  de.SetByteValue(value.data(), uint32_t(value.size()));
  ds.Replace(de);
}

/// Adds a sequence of undefined length (LanguageCodeSequence, (0008,0006): before the
/// RecognitionCode and the image attributes) of two items of undefined length, the second holding
/// a nested sequence of undefined length, as real CTs carry them.
inline void AddUndefinedLengthSequence(gdcm::DataSet& ds) {
  auto item = [](const std::string& code) {
    gdcm::Item it;
    it.SetVLToUndefined();
    SetTag(it.GetNestedDataSet(), 0x0008, 0x0100, gdcm::VR::SH, code);
    SetTag(it.GetNestedDataSet(), 0x0008, 0x0102, gdcm::VR::SH, "RFC5646");
    return it;
  };
  gdcm::SmartPointer<gdcm::SequenceOfItems> inner = new gdcm::SequenceOfItems;
  inner->SetLengthToUndefined();
  inner->AddItem(item("en-GB"));
  gdcm::Item second = item("fr");
  gdcm::DataElement nested(gdcm::Tag(0x0008, 0x0121)); // EquivalentCodeSequence
  nested.SetVR(gdcm::VR::SQ);
  nested.SetValue(*inner);
  nested.SetVLToUndefined();
  second.GetNestedDataSet().Replace(nested);
  gdcm::SmartPointer<gdcm::SequenceOfItems> sq = new gdcm::SequenceOfItems;
  sq->SetLengthToUndefined();
  sq->AddItem(item("en"));
  sq->AddItem(second);
  gdcm::DataElement de(gdcm::Tag(0x0008, 0x0006));
  de.SetVR(gdcm::VR::SQ);
  de.SetValue(*sq);
  de.SetVLToUndefined();
  ds.Replace(de);
}

/// The byte offset of the first occurrence of `bytes` in `file` (npos when absent).
inline size_t FindBytes(const fs::path& file, const std::string& bytes) {
  std::ifstream in(file, std::ios::binary);
  const std::string all((std::istreambuf_iterator<char>(in)), {});
  return all.find(bytes);
}

/// Overwrite `bytes` at `offset` of `file`.
inline void PatchBytes(const fs::path& file, size_t offset, const std::string& bytes) {
  std::fstream f(file, std::ios::binary | std::ios::in | std::ios::out);
  f.seekp(std::streamoff(offset));
  f.write(bytes.data(), std::streamsize(bytes.size()));
}

/// A small block phantom series (fast to write and read).
inline void WriteBlock(const fs::path& dir, bm::DicomWriteOptions dicom = {}) {
  bm::WritePhantomSeries("block", dir.string(), {}, dicom);
}

} // namespace bmtest
