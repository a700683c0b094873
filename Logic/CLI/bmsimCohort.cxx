// bmsim cohort - plans every case of a cohort (bmCohort.h): each case is `bmsim plan` in a child
// process (a case that crashes or fails does not stop the others), N at a time on this machine, or
// one case per call (--case ID: what a cluster's task runs, Utilities/cohort-dask.py); cases
// already done are skipped; the table DIR/cohort.csv is written (atomically) at the end, or alone
// with --collect.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "bmAtomicFile.h"
#include "bmCohort.h"
#include "bmsimArgs.h"
#include "bmsimCommand.h"

extern char** environ;

namespace fs = std::filesystem;

namespace {

void CohortOptions(bm::cli::ParsedArgs& p) {
  p.Words("CASES.csv", "the case list: a CSV with the columns id, ct and optionally side "
                       "(left or right); a CT is anything bmsim plan reads (a DICOM folder, a "
                       "volume file, a pacs:// series), relative paths from the list's folder");
  p.Value("o,out", "DIR",
          "the cohort's folder (required): DIR/cases/ID/ (each case's plan), "
          "DIR/cases/ID.log, DIR/cases/ID.failed, DIR/cohort.csv");
  p.Int("jobs", 1, 64, "cases planned at once on this machine (default 1)");
  p.Value("case", "ID", "plan only this case (a cluster task's work; the table is not written)");
  p.Flag("collect", "write DIR/cohort.csv from the cases' folders only, planning nothing");
  p.Footer("Each case runs `bmsim plan CT --out DIR/cases/ID --quiet [--side S]` in its own "
           "process: a case that fails (its message kept in DIR/cases/ID.failed) does not stop "
           "the others. A case whose plan report exists (planned, or no glenoid found with the "
           "reason) is skipped, so a rerun goes on where the last one stopped and retries the "
           "failed cases. DIR/cohort.csv: id, ct, side, status (planned, no_glenoid, failed, "
           "pending), 3D and Friedman version, inclination, glenoid height and width, the plan's "
           "correction, and the reason or warnings. On a cluster: Utilities/cohort-dask.py (Dask) "
           "runs one --case per task and --collect at the end. Exit status 0 when every case was "
           "planned or has no glenoid, 1 when one failed.");
}

/// Starts `bmsim plan` for the case, its stderr (and stdout) into the case's log. Returns the
/// child's PID.
pid_t StartCase(const fs::path& dir, const bm::CohortCase& c) {
  fs::create_directories(dir / "cases");
  std::vector<std::string> args = {
      "bmsim", "plan", c.ct, "--out", bm::CohortCaseFolder(dir, c).string(), "--quiet"};
  if (!c.side.empty()) {
    args.push_back("--side");
    args.push_back(c.side);
  }
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string log = bm::CohortCaseLog(dir, c).string();
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0)
    throw std::runtime_error("cannot start bmsim plan for case " + c.id);
  return pid;
}

/// Records how the case's process ended: a failure's message (the log's last line) in
/// ID.failed, removed when the case was planned or has no glenoid.
void FinishCase(const fs::path& dir, const bm::CohortCase& c, int status) {
  const fs::path failed = bm::CohortCaseFailure(dir, c);
  std::error_code ec;
  if (bm::CohortCaseDone(dir, c)) {
    fs::remove(failed, ec);
    return;
  }
  std::string last, line;
  std::ifstream log(bm::CohortCaseLog(dir, c));
  while (std::getline(log, line))
    if (!line.empty())
      last = line;
  const std::string how = WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                          : WIFSIGNALED(status)
                              ? "killed by signal " + std::to_string(WTERMSIG(status))
                              : "ended";
  bm::WriteFileAtomic(failed.string(), (last.empty() ? how : last + " (" + how + ")") + "\n");
}

int CohortCommand(const bm::cli::ParsedArgs& p) {
  if (p.Positional().size() != 1)
    throw bm::cli::UsageError("name one case list (CASES.csv)");
  const auto out = p.Get("out");
  if (!out)
    throw bm::cli::UsageError("--out DIR is required");
  if (p.Has("case") && p.Has("collect"))
    throw bm::cli::UsageError("--case and --collect: one or the other");
  const std::vector<bm::CohortCase> cases = bm::ReadCohortCases(p.Positional()[0]);
  const fs::path dir = fs::absolute(*out);
  fs::create_directories(dir / "cases");

  std::vector<bm::CohortCase> toRun;
  int skipped = 0;
  if (const auto only = p.Get("case")) {
    const auto it = std::find_if(cases.begin(), cases.end(),
                                 [&](const bm::CohortCase& c) { return c.id == *only; });
    if (it == cases.end())
      throw bm::cli::UsageError("no case '" + *only + "' in " + p.Positional()[0]);
    if (bm::CohortCaseDone(dir, *it))
      skipped = 1;
    else
      toRun.push_back(*it);
  } else if (!p.Has("collect")) {
    for (const auto& c : cases)
      if (bm::CohortCaseDone(dir, c))
        ++skipped;
      else
        toRun.push_back(c);
  }
  const int jobs = int(p.GetInt("jobs", 1, 64).value_or(1));
  std::map<pid_t, bm::CohortCase> running;
  size_t next = 0;
  while (next < toRun.size() || !running.empty()) {
    while (next < toRun.size() && int(running.size()) < jobs) {
      const bm::CohortCase& c = toRun[next++];
      std::error_code ec;
      fs::remove_all(bm::CohortCaseFolder(dir, c), ec); // a case not done left nothing usable
      running[StartCase(dir, c)] = c;
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0)
      break;
    const auto it = running.find(pid);
    if (it == running.end())
      continue;
    FinishCase(dir, it->second, status);
    std::cout << "case " << it->second.id << ": " << bm::CohortRowFor(dir, it->second).status
              << "\n";
    running.erase(it);
  }

  std::vector<bm::CohortRow> rows;
  std::map<std::string, int> counts;
  for (const auto& c : cases) {
    rows.push_back(bm::CohortRowFor(dir, c));
    ++counts[rows.back().status];
  }
  if (!p.Has("case")) {
    bm::WriteFileAtomic((dir / "cohort.csv").string(), bm::CohortTableCsv(rows));
    std::cout << "wrote " << (dir / "cohort.csv").string() << ": ";
  } else {
    if (skipped)
      std::cout << "case " << *p.Get("case") << ": done before, skipped\n";
    return 0; // the case's outcome is in its folder; the task itself succeeded
  }
  std::cout << counts["planned"] << " planned, " << counts["no_glenoid"] << " no glenoid, "
            << counts["failed"] << " failed, " << counts["pending"] << " pending; " << toRun.size()
            << " run now, " << skipped << " done before (skipped)\n";
  return counts["failed"] > 0 ? 1 : 0;
}

} // namespace

BM_REGISTER_COMMAND(cohort,
                    "plan every shoulder CT of a case list (in parallel, or a case per cluster "
                    "task) into one table of measurements",
                    CohortOptions, CohortCommand);
