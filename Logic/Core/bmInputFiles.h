// bmInputFiles.h - the files a command reads, so that no output it writes replaces one of them
// (Docs/Reliability.md, "Outputs"). Paths are compared as the files they lead to: links (of the
// path and of its folders) are resolved, and an existing output that is a hard link to an input
// is found by its device and inode. A folder added whole (a DICOM series) holds inputs everywhere
// inside it.
#pragma once

#include <string>
#include <vector>

namespace bm {

class InputFiles {
public:
  /// Adds the file `path`, read as `role` (e.g. "the scene file"). A path that does not exist is
  /// kept as given (resolved as far as it exists).
  void AddFile(const std::string& path, const std::string& role);
  /// Adds the folder `path` whose files are read as `role` (e.g. "the DICOM series").
  void AddFolder(const std::string& path, const std::string& role);

  /// Throws std::runtime_error "<what> 'OUT' is <role> 'IN': writing it would replace it; choose
  /// another ..." when `output` is one of the files added or lies inside a folder added.
  void CheckOutput(const std::string& output, const std::string& what) const;

  bool Empty() const { return Entries_.empty(); }

private:
  struct Entry {
    std::string given, resolved, role;
    bool folder = false;
  };
  std::vector<Entry> Entries_;
};

} // namespace bm
