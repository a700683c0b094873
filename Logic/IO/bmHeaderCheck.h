// bmHeaderCheck.h - validate a volume file's header before any allocation or decode
// (Docs/Reliability.md, "CT import").
//
// NRRD (.nrrd/.nhdr), MetaImage (.mha/.mhd) and NIfTI-1 (.nii/.nii.gz) headers are parsed here,
// independently of ITK, and refused with std::runtime_error naming the file and the problem when:
//  - the input, or a data file it names, is not a regular file (FIFO, device, socket, folder);
//  - the header does not start as its format must (e.g. a NRRD file named .mha), is longer than
//    kMaxHeaderLines lines or kMaxHeaderBytes bytes, or a size field does not parse;
//  - the image is not 3-D (a 4-D image with a 4th size above 1, a 2-D image) or has a zero size,
//    or holds more values per voxel than HeaderLimits::maxComponents;
//  - the voxels as float need more bytes than the memory limit (CheckMemoryBudget);
//  - a spacing is not finite and > 0, an origin or direction value is not finite, a direction
//    axis has zero length, a NIfTI rescale slope/intercept is not finite;
//  - a detached data file is given by an absolute path or with "..", or resolves (through links)
//    outside the header's folder, unless allowDataOutsideFolder; a multi-file list or pattern;
//  - the data are stored raw (uncompressed) and the file holds fewer bytes than the header
//    declares (truncated), or a gzip stream ends before the declared bytes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "bmInputFiles.h"

namespace bm {

/// Longest accepted text header (NRRD, MetaImage): lines and bytes.
constexpr int kMaxHeaderLines = 4096;
constexpr uint64_t kMaxHeaderBytes = uint64_t(1) << 20;

struct HeaderLimits {
  uint64_t maxMemoryBytes = 0;         ///< as ReadOptions::maxMemoryBytes (0 = default limit)
  bool allowDataOutsideFolder = false; ///< accept detached data files anywhere
  /// Values per voxel accepted (NRRD: a 4-D image whose first axis holds them; MetaImage:
  /// ElementNumberOfChannels). 1 for a CT; a saved voxmap has 2 (bone fraction, material).
  int maxComponents = 1;
  /// As ReadOptions::extraBytesPerVoxel: bytes per voxel the caller needs beside the CT's float.
  uint64_t extraBytesPerVoxel = 0;
};

/// What the header check found (used as evidence for the intensity decision).
struct VolumeHeader {
  std::string format;             ///< "NRRD", "MetaImage" or "NIfTI"
  uint64_t dims[3] = {0, 0, 0};   ///< voxels along each axis
  int componentBytes = 0;         ///< bytes per stored value
  int components = 1;             ///< stored values per voxel
  bool integerType = true;        ///< stored values are integers
  bool hasRescale = false;        ///< NIfTI scl_slope/scl_inter present (non-identity)
  std::filesystem::path dataFile; ///< where the voxels are (the header file when attached)
};

/// Throw unless `path` is a regular file (following links); `role` names it in the message
/// (e.g. "input", "data file").
void CheckRegularFile(const std::filesystem::path& path, const std::string& role);

/// Check the header of `file`, whose format is "NRRD", "MetaImage" or "NIfTI" (see above).
VolumeHeader CheckVolumeHeader(const std::filesystem::path& file, const std::string& format,
                               const HeaderLimits& limits);

/// The detached data file a NRRD (.nhdr/.nrrd "data file") or MetaImage (.mhd/.mha
/// ElementDataFile) header names, taken relative to the header's folder; empty when the data are
/// attached, the file is of another format or its header does not parse (the reader names that).
std::filesystem::path DetachedDataFile(const std::filesystem::path& header);

/// Adds to `inputs` the files reading the CT (or saved voxmap) `input` reads: the input, the
/// detached data file its header names, and for a DICOM series its folder (the input folder, or
/// the folder of a DICOM file given alone), each named after `role`.
void AddCTInputs(InputFiles& inputs, const std::string& input,
                 const std::string& role = "the input");

/// Throw when `output` is a file the CT `input` is read from (the input, a detached data file
/// its header names, through links) or lies inside the input folder (a DICOM series, also when
/// one of its files is the input): writing there would replace or alter the patient's data.
void CheckOutputIsNotInput(const std::string& input, const std::string& output);

} // namespace bm
