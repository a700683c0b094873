// bmHeaderCheck.cxx - see bmHeaderCheck.h: the regular-file check, the dispatch to each format's
// header check (bmHeaderCheckNrrd.cxx, bmHeaderCheckMeta.cxx, bmHeaderCheckNifti.cxx), and the
// files a CT is read from (detached data files, a DICOM series' folder).
#include "bmHeaderCheck.h"
#include "bmHeaderCheckInternal.h"

#include "bmDicomFileCheck.h"
#include "bmInputFiles.h"
#include "bmRegularFile.h"

#include <sys/stat.h>

#include <stdexcept>

namespace fs = std::filesystem;

namespace bm {

namespace {

using headercheck::CheckMeta;
using headercheck::CheckNifti;
using headercheck::CheckNrrd;
using headercheck::HeaderLines;
using headercheck::Lower;
using headercheck::Q;
using headercheck::Trim;

} // namespace

void CheckRegularFile(const fs::path& path, const std::string& role) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw std::runtime_error(role + " " + Q(path) + " does not exist or cannot be opened");
  const char* kind = nullptr;
  if (S_ISDIR(st.st_mode))
    kind = "a folder";
  else if (S_ISFIFO(st.st_mode))
    kind = "a FIFO (named pipe)";
  else if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode))
    kind = "a device";
  else if (S_ISSOCK(st.st_mode))
    kind = "a socket";
  else if (!S_ISREG(st.st_mode))
    kind = "not a regular file";
  const std::string why = kind ? std::string() : NotARegularFile(path.string());
  if (!kind && !why.empty()) // a kernel interface file (/proc/kmsg blocks the first read)
    kind = why.c_str();
  if (kind)
    throw std::runtime_error(role + " " + Q(path) + " is " + kind + ", not a regular file");
}

VolumeHeader CheckVolumeHeader(const fs::path& file, const std::string& format,
                               const HeaderLimits& limits) {
  CheckRegularFile(file, "the input");
  if (format == "NRRD")
    return CheckNrrd(file, limits);
  if (format == "MetaImage")
    return CheckMeta(file, limits);
  if (format == "NIfTI")
    return CheckNifti(file, limits);
  throw std::invalid_argument("CheckVolumeHeader: unknown format " + format);
}

fs::path DetachedDataFile(const fs::path& header) {
  const std::string ext = Lower(header.extension().string());
  const bool nrrd = ext == ".nrrd" || ext == ".nhdr", meta = ext == ".mha" || ext == ".mhd";
  if (!(nrrd || meta))
    return {};
  std::error_code ec;
  if (!fs::is_regular_file(header, ec))
    return {};
  try {
    uint64_t bytes = 0;
    const auto lines = HeaderLines(header, bytes, [&](const std::string& l) {
      return nrrd ? l.empty() : Lower(Trim(l)).rfind("elementdatafile", 0) == 0;
    });
    for (const std::string& line : lines) {
      const std::string l = Trim(line);
      std::string key, value;
      if (nrrd) {
        const size_t colon = l.find(": ");
        if (colon == std::string::npos || l.find(":=") != std::string::npos)
          continue;
        key = Lower(Trim(l.substr(0, colon)));
        value = Trim(l.substr(colon + 2));
        if (key != "data file" && key != "datafile")
          continue;
      } else {
        const size_t eq = l.find('=');
        if (eq == std::string::npos)
          continue;
        key = Lower(Trim(l.substr(0, eq)));
        value = Trim(l.substr(eq + 1));
        if (key != "elementdatafile" || Lower(value) == "local")
          continue;
      }
      if (value.empty() || value.find('%') != std::string::npos || value.rfind("LIST", 0) == 0)
        return {};
      const fs::path p(value);
      const fs::path folder = header.parent_path().empty() ? fs::path(".") : header.parent_path();
      return p.is_absolute() ? p : folder / p;
    }
  } catch (const std::exception&) {
  }
  return {};
}

void AddCTInputs(InputFiles& inputs, const std::string& input, const std::string& role) {
  std::error_code ec;
  if (fs::is_directory(input, ec)) {
    inputs.AddFolder(input, role + " folder");
  } else {
    inputs.AddFile(input, role);
    const fs::path data = DetachedDataFile(input);
    if (!data.empty())
      inputs.AddFile(data.string(), "the data file of " + role);
    if (NotARegularFile(input).empty() && HasDicomMagic(input)) { // a FIFO would block the read
      const fs::path folder = fs::path(input).parent_path();
      inputs.AddFolder(folder.empty() ? "." : folder.string(),
                       "the folder of " + role + "'s DICOM series");
    }
  }
}

void CheckOutputIsNotInput(const std::string& input, const std::string& output) {
  InputFiles inputs;
  AddCTInputs(inputs, input);
  try {
    inputs.CheckOutput(output, "the output");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + " (it would overwrite the CT)");
  }
}

} // namespace bm
