// bmsimStagedOutput.h - a run's outputs appear together: they are written into a hidden staging
// folder beside them (bm::TemporarySibling's pattern, ".run.tmp-PID-N" in the output folder), then
// moved into the output folder one by one, the file that says the set is complete (summary.json)
// last. A run that fails or is killed leaves nothing in the output folder but, when killed, its
// staging folder, which the next run writing to that folder removes (bm::RemoveStaleTemporaries).
// A run into the folder of an earlier run removes that run's outputs it does not write itself (a
// report and pictures of another scene beside the new summary), as the folder's manifest lists
// them.
#pragma once

#include <string>

namespace bm::cli {

class StagedOutput {
public:
  /// Creates the output folder (if missing) and a fresh staging folder in it; removes the
  /// staging folders of runs that no longer exist. Throws std::runtime_error naming the folder
  /// when it cannot be created.
  explicit StagedOutput(const std::string& outDir);
  /// Removes the staging folder and what is in it unless Commit() ran.
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  /// The staging folder: write the outputs here.
  const std::string& Path() const { return Stage_; }
  /// Moves every file and folder of the staging folder into the output folder (replacing what
  /// is there of the same name), `last` (e.g. "summary.json") after all others, then removes the
  /// staging folder. The outputs an earlier run listed in the folder's manifest (kManifest) that
  /// this run does not write are removed first, and the manifest then lists this run's. Throws
  /// std::runtime_error naming the file that cannot be moved.
  void Commit(const std::string& last = "summary.json");

  /// The hidden file, in the output folder, that lists the outputs of the run that wrote it.
  static constexpr const char* kManifest = ".bmsim-outputs";

private:
  std::string Out_, Stage_;
  bool Committed_ = false;
};

} // namespace bm::cli
