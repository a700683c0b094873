// bmCohort.h - a cohort of shoulder CTs planned one by one (bmsim cohort, on this machine or one
// task per case on a cluster): the case list, where each case's plan goes, and the one table of
// measurements made from the cases' plan reports (Docs/Planning.md "Cohorts").
//
// Layout under the cohort's folder DIR: DIR/cases/ID/ is the plan of case ID as bmsim plan writes
// it (plan_report.json, the scenes, the report), DIR/cases/ID.log its messages, DIR/cases/ID.failed
// why it failed (a case that failed leaves no plan folder: bmsim plan writes nothing half), and
// DIR/cohort.csv the table. A case is done when its plan_report.json exists (planned, or no
// glenoid found, with the reason): a rerun skips it, and tries a failed one again.
//
// Units: deg, mm.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace bm {

/// One case: an ID (letters, digits, '.', '_', '-'; unique), its CT (anything bmsim plan reads:
/// a DICOM folder, a volume file, a pacs:// series) and the side to plan ("", left or right).
struct CohortCase {
  std::string id, ct, side;
};

/// Reads a case list: CSV with a header naming the columns id and ct (side optional), one case
/// per record; blank lines are skipped. A relative CT path is taken from the list's folder.
/// Throws std::runtime_error naming the file and the line: a missing column, a bad or repeated
/// ID, an empty CT, a side other than left/right/empty, no case at all.
std::vector<CohortCase> ReadCohortCases(const std::string& path);

/// Where a case's plan, messages and failure go under the cohort's folder.
std::filesystem::path CohortCaseFolder(const std::filesystem::path& dir, const CohortCase& c);
std::filesystem::path CohortCaseLog(const std::filesystem::path& dir, const CohortCase& c);
std::filesystem::path CohortCaseFailure(const std::filesystem::path& dir, const CohortCase& c);
/// Whether the case's plan report is there (planned or no glenoid).
bool CohortCaseDone(const std::filesystem::path& dir, const CohortCase& c);

/// One row of the table.
struct CohortRow {
  CohortCase c;
  /// planned | no_glenoid | failed | pending (not run yet)
  std::string status;
  std::string side; ///< the side planned (left, right), "" when not planned
  /// Measurements (NaN when not made): 3D version, Friedman's 2D version, inclination, the
  /// glenoid's height and width, and the plan's correction (deg, mm).
  double version3dDeg, friedmanVersionDeg, inclinationDeg, heightMm, widthMm, correctionDeg;
  std::string reason; ///< why not planned (no glenoid, the failure's message), or warnings
};

/// The row of one case from what its folder holds.
CohortRow CohortRowFor(const std::filesystem::path& dir, const CohortCase& c);

/// The table's CSV (header, then one row per case in the list's order; empty cells for
/// measurements not made).
std::string CohortTableCsv(const std::vector<CohortRow>& rows);

} // namespace bm
