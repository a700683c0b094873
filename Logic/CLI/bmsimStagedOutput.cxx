// bmsimStagedOutput.cxx - see bmsimStagedOutput.h.
#include "bmsimStagedOutput.h"

#include "bmAtomicFile.h"

#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace bm::cli {

namespace fs = std::filesystem;

StagedOutput::StagedOutput(const std::string& outDir) : Out_(outDir) {
  std::error_code ec;
  fs::create_directories(outDir, ec);
  if (ec || !fs::is_directory(outDir))
    throw std::runtime_error("cannot create the output folder '" + outDir +
                             "': " + (ec ? ec.message() : "not a folder"));
  Stage_ = bm::TemporarySibling((fs::path(outDir) / "run").string()); // also clears stale ones
  if (!fs::create_directory(Stage_, ec) || ec)
    throw std::runtime_error("cannot create the staging folder '" + Stage_ + "': " + ec.message());
}

StagedOutput::~StagedOutput() {
  if (!Committed_) {
    std::error_code ec;
    fs::remove_all(Stage_, ec);
  }
}

void StagedOutput::Commit(const std::string& last) {
  std::vector<fs::path> entries;
  for (const auto& e : fs::directory_iterator(Stage_))
    if (e.path().filename() != last)
      entries.push_back(e.path());
  if (fs::exists(fs::path(Stage_) / last))
    entries.push_back(fs::path(Stage_) / last);
  // What an earlier run wrote here and this one does not (another scene's report and pictures)
  // goes before the new set is complete: the folder holds one run's outputs. Only names the
  // earlier run listed are removed, never other files.
  const fs::path manifest = fs::path(Out_) / kManifest;
  std::set<std::string> now;
  for (const fs::path& from : entries)
    now.insert(from.filename().string());
  {
    std::ifstream in(manifest);
    for (std::string name; std::getline(in, name);)
      if (!name.empty() && name.find('/') == std::string::npos && name != "." && name != ".." &&
          !now.count(name)) {
        std::error_code ec;
        fs::remove_all(fs::path(Out_) / name, ec);
      }
  }
  {
    std::string list;
    for (const std::string& name : now)
      list += name + "\n";
    bm::WriteFileAtomic(manifest.string(), list);
  }
  for (const fs::path& from : entries) {
    const fs::path to = fs::path(Out_) / from.filename();
    std::error_code ec;
    if (fs::is_directory(to) && !fs::is_directory(from))
      throw std::runtime_error("cannot write '" + to.string() + "': a folder of that name exists");
    if (fs::is_directory(from))
      fs::remove_all(to, ec); // a folder replaces its older self whole
    fs::rename(from, to, ec);
    if (ec)
      throw std::runtime_error("cannot move '" + from.string() + "' to '" + to.string() +
                               "': " + ec.message());
  }
  Committed_ = true;
  std::error_code ec;
  fs::remove_all(Stage_, ec);
}

} // namespace bm::cli
