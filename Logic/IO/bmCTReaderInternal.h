// bmCTReaderInternal.h - private to the CT reader (bmCTReader.h), shared by its parts: a DICOM
// slice's header and a scanned folder's series (bmCTReaderDicomScan.cxx), the DICOM series reader
// (bmCTReaderDicomSeries.cxx), the single-volume reader (bmCTReaderVolume.cxx) and the dispatch
// (bmCTReader.cxx). Not part of BMIO's interface: include it only from those files.
#pragma once

#include "bmCTReader.h"

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace bm::ctreader {

inline std::string ToLower(std::string s) {
  for (auto& c : s)
    c = char(std::tolower((unsigned char)c));
  return s;
}

/// Largest deviation of a direction cosine's length from 1, and of the dot product of two
/// directions from 0 (GDCM's own tolerance for ImageOrientationPatient).
constexpr double kOrientationTolerance = 1e-3;

// ---------------------------------------------------------------------------------------------
// DICOM folders (bmCTReaderDicomScan.cxx)

struct SliceHeader {
  std::filesystem::path file;
  std::string seriesUID, modality, description, transferSyntax, frames;
  std::string seriesNumber, studyUID, rescaleType, sopClassUID;
  std::vector<double> rescaleSlope, rescaleIntercept; // empty when absent
  int bitsAllocated = 0;
  std::string seriesId; // seriesUID, or a "noUID-..." id from other attributes
  int rows = 0, cols = 0;
  std::vector<double> pixelSpacing, ipp, iop;
  bool hasPixelData = false;
  double position = 0; // along the slice normal, mm
};

struct ScannedFolder {
  std::map<std::string, std::vector<SliceHeader>> series; // by series id
  std::vector<SliceHeader> withoutImage;                  // DICOM files that end without pixel data
  std::vector<std::string> notDicom;                      // names of files skipped as not DICOM
};

/// A DICOM file's header, read with GDCM up to its pixel data and checked (truncation, pixel data
/// length, rows and columns); hasPixelData false for a complete DICOM file without an image.
SliceHeader ReadSliceHeader(const std::filesystem::path& file);

/// "skipped N files that are not DICOM: a, b, c" (at most 5 named).
std::string SkippedText(const std::vector<std::string>& names);

/// Read the headers of the folder's files. magicOnly: only files with the DICM magic (the folder
/// of a single file given on the command line may hold other files).
ScannedFolder ScanFolder(const std::filesystem::path& dir, const Progress& progress,
                         bool magicOnly = false);

/// Choose the series to read from a scanned folder (opt.seriesUID, or the only one).
std::vector<SliceHeader>& ChooseSeries(ScannedFolder& scanned, const std::filesystem::path& dir,
                                       const ReadOptions& opt);

/// A file of the chosen series that ends without its image (cut short at an element's end) is a
/// damaged slice, not a file to leave out: refused by name.
void CheckNoSliceWithoutImage(const ScannedFolder& scanned, const std::vector<SliceHeader>& slices,
                              const std::filesystem::path& dir);

// ---------------------------------------------------------------------------------------------
// Reading

/// A CT as read (values as the file gives them, its own rescale applied) and what the file says
/// about its values, for the intensity decision (bmIntensityMapping.h).
struct ReadOutcome {
  CTImage ct;
  IntensityEvidence evidence;
};

/// A DICOM folder's series (ReadOptions::seriesUID, or its only one), read
/// (bmCTReaderDicomSeries.cxx).
ReadOutcome ReadDicomFolder(const std::filesystem::path& dir, const ReadOptions& opt,
                            const Progress& progress);

/// A single DICOM file: the series it belongs to in its folder (bmCTReaderDicomSeries.cxx).
ReadOutcome ReadDicomFile(const std::filesystem::path& file, const ReadOptions& opt,
                          const Progress& progress);

/// A NRRD, MetaImage or NIfTI volume, its header checked first (bmCTReaderVolume.cxx).
ReadOutcome ReadVolumeFile(const std::filesystem::path& file, const ReadOptions& opt,
                           const Progress& progress);

} // namespace bm::ctreader
