#include "bmInputFiles.h"

#include <filesystem>
#include <stdexcept>

namespace fs = std::filesystem;

namespace bm {

namespace {

/// The path through every link, as far as it exists (the rest appended as given).
std::string Resolved(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec)
    p = fs::absolute(path, ec).lexically_normal();
  return p.string();
}

bool Inside(const std::string& file, const std::string& folder) {
  const fs::path rel = fs::path(file).lexically_relative(folder);
  return !rel.empty() && *rel.begin() != ".." && rel != ".";
}

} // namespace

void InputFiles::AddFile(const std::string& path, const std::string& role) {
  if (!path.empty())
    Entries_.push_back({path, Resolved(path), role, false});
}

void InputFiles::AddFolder(const std::string& path, const std::string& role) {
  if (!path.empty())
    Entries_.push_back({path, Resolved(path), role, true});
}

void InputFiles::CheckOutput(const std::string& output, const std::string& what) const {
  const std::string out = Resolved(output);
  std::error_code ec;
  const bool outExists = fs::exists(output, ec);
  for (const Entry& e : Entries_) {
    const bool same = out == e.resolved || (outExists && !e.folder && fs::exists(e.given, ec) &&
                                            fs::equivalent(output, e.given, ec)); // a hard link
    if (same)
      throw std::runtime_error(
          what + " '" + output + "' is " + e.role + " '" + e.given + "'" +
          (out != fs::absolute(output, ec).lexically_normal().string() ? " (through a link)" : "") +
          ": writing it would replace it; choose another file");
    if (e.folder && Inside(out, e.resolved))
      throw std::runtime_error(what + " '" + output + "' lies inside " + e.role + " '" + e.given +
                               "': writing there would alter it; choose a file elsewhere");
  }
}

} // namespace bm
