// bmPlanFiles.cxx - see bmPlanFiles.h.
#include "bmPlanFiles.h"

#include "bmAtomicFile.h"

#include <filesystem>
#include <utility>
#include <vector>

namespace bm {

std::vector<std::string> WritePlanFiles(const std::string& dir, const PlanReportInput& report,
                                        const PlanScenes* scenes) {
  namespace fs = std::filesystem;
  std::vector<std::pair<std::string, std::string>> files;
  if (scenes) {
    files.emplace_back("plan.json", scenes->plan.dump(2) + "\n");
    files.emplace_back("step1-guide-pin.json", scenes->pin.dump(2) + "\n");
    files.emplace_back("step2-ream.json", scenes->ream.dump(2) + "\n");
  }
  files.emplace_back("plan_report.md", PlanReportMarkdown(report));
  files.emplace_back("plan_report.html", PlanReportHtml(report));
  files.emplace_back("plan_report.json", PlanReportJson(report).dump(2) + "\n");
  fs::create_directories(dir);
  std::vector<std::string> names;
  for (auto& [name, text] : files) {
    names.push_back(name);
    name = (fs::path(dir) / name).string();
  }
  WriteFilesAtomic(files);
  return names;
}

} // namespace bm
