// bmHostileCorpus.h - the hostile-input corpus run against bmsim (TestBmsimHostileCorpus.cxx):
// the case list the groups fill (HostileCorpusOptions.cxx: every numeric, point and word option;
// HostileCorpusFiles.cxx: every reader of user files) and the runner reads.
#pragma once

#include "bmHostileFiles.h"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace bmcorpus {

namespace fs = std::filesystem;

extern std::string gBmsim; ///< the bmsim under test
extern fs::path gWork;     ///< the scratch folder
extern fs::path gBase;     ///< valid inputs made once: a DICOM series, recordings

struct Case {
  std::string name;
  std::vector<std::string> args; ///< bmsim's arguments: "{in}" and "{out}" are the case's folders
  std::vector<std::string> needles;
  std::function<void(const fs::path& in)> make; ///< writes the case's inputs into `in`
};

extern std::vector<Case> gCases;

/// Adds a case: bmsim `args` must be refused with every needle in its stderr.
void Add(std::string name, std::vector<std::string> args, std::vector<std::string> needles,
         std::function<void(const fs::path&)> make = {});
/// A number as bmsim's messages print it (12 significant digits).
std::string Format(double v);
/// A case input maker writing `bytes` to `name` in the input folder.
std::function<void(const fs::path&)> Writes(const std::string& name, const std::string& bytes);

/// The option cases (HostileCorpusOptions.cxx).
void OptionCases();
/// The valid inputs the file cases damage (a DICOM series and a recording, written by bmsim into
/// gBase); false when bmsim cannot make them.
bool MakeBase();
/// The file cases (HostileCorpusFiles.cxx; the tables' cases, HostileCorpusTables.cxx, among
/// them).
void FileCases();
void TableCases();

} // namespace bmcorpus
