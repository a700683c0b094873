// A cohort's case list and table (bmCohort.h): the list read with relative CTs taken from its
// folder, bad lists refused naming the line; each case's row from what its folder holds
// (planned, no glenoid with the reason, failed with its message, pending); the table's CSV.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "bmCohort.h"
#include "bmCsv.h"

namespace fs = std::filesystem;

namespace {

fs::path Scratch(const std::string& name) {
  const fs::path d = fs::path(testing::TempDir()) / ("bm-cohort-" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string Refusal(const fs::path& list, const std::string& text) {
  std::ofstream(list) << text;
  try {
    bm::ReadCohortCases(list.string());
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(Cohort, TheCaseListIsReadAndBadOnesAreRefusedByLine) {
  const fs::path d = Scratch("list");
  std::ofstream(d / "cases.csv") << "side,id,ct\n\nright,A-1,ct/a\n,b_2,/abs/b\nleft,c.3,"
                                    "\"pacs://PACS@h:104/1.2.3\"\n";
  const auto cases = bm::ReadCohortCases((d / "cases.csv").string());
  ASSERT_EQ(cases.size(), 3u);
  EXPECT_EQ(cases[0].id, "A-1");
  EXPECT_EQ(cases[0].ct, (d / "ct/a").string()); // from the list's folder
  EXPECT_EQ(cases[0].side, "right");
  EXPECT_EQ(cases[1].ct, "/abs/b");
  EXPECT_EQ(cases[2].ct, "pacs://PACS@h:104/1.2.3"); // a PACS series is kept as given

  const fs::path bad = d / "bad.csv";
  EXPECT_NE(Refusal(bad, "name,ct\nA,x\n").find("id and ct"), std::string::npos);
  EXPECT_NE(Refusal(bad, "id,ct\nA,x\nA,y\n").find("bad.csv:3"), std::string::npos);
  EXPECT_NE(Refusal(bad, "id,ct\n../up,x\n").find("'../up'"), std::string::npos);
  EXPECT_NE(Refusal(bad, "id,ct\na/b,x\n").find("letters, digits"), std::string::npos);
  EXPECT_NE(Refusal(bad, "id,ct\nA,\n").find("names no CT"), std::string::npos);
  EXPECT_NE(Refusal(bad, "id,ct,side\nA,x,up\n").find("'up'"), std::string::npos);
  EXPECT_NE(Refusal(bad, "id,ct\n").find("no case"), std::string::npos);
  EXPECT_THROW(bm::ReadCohortCases((d / "missing.csv").string()), std::runtime_error);
}

TEST(Cohort, EachRowIsWhatItsCaseFolderHolds) {
  const fs::path d = Scratch("rows");
  const bm::CohortCase planned{"p", "/ct/p", ""}, none{"n", "/ct/n", "left"},
      failed{"f", "/ct/f", ""}, pending{"w", "/ct/w", ""};
  fs::create_directories(bm::CohortCaseFolder(d, planned));
  std::ofstream(bm::CohortCaseFolder(d, planned) / "plan_report.json")
      << R"({"status": "planned", "landmarks": {"side": "right"},
             "measurements": {"version_3d_deg": -11.5, "friedman_version_deg": -10.25,
                              "inclination_deg": 7.75, "glenoid_height_mm": 40,
                              "glenoid_width_mm": 29},
             "plan": {"correction_deg": 13.5, "warnings": ["w1", "w2"]}})";
  fs::create_directories(bm::CohortCaseFolder(d, none));
  std::ofstream(bm::CohortCaseFolder(d, none) / "plan_report.json")
      << R"({"status": "no_glenoid", "message": "no two bones face each other"})";
  std::ofstream(bm::CohortCaseFailure(d, failed)) << "bmsim plan: error: bad CT (exit status 1)\n";

  const bm::CohortRow p = bm::CohortRowFor(d, planned);
  EXPECT_TRUE(bm::CohortCaseDone(d, planned));
  EXPECT_EQ(p.status, "planned");
  EXPECT_EQ(p.side, "right");
  EXPECT_EQ(p.version3dDeg, -11.5);
  EXPECT_EQ(p.friedmanVersionDeg, -10.25);
  EXPECT_EQ(p.inclinationDeg, 7.75);
  EXPECT_EQ(p.correctionDeg, 13.5);
  EXPECT_EQ(p.reason, "w1; w2");
  const bm::CohortRow n = bm::CohortRowFor(d, none);
  EXPECT_EQ(n.status, "no_glenoid");
  EXPECT_EQ(n.reason, "no two bones face each other");
  EXPECT_TRUE(std::isnan(n.version3dDeg));
  const bm::CohortRow f = bm::CohortRowFor(d, failed);
  EXPECT_FALSE(bm::CohortCaseDone(d, failed));
  EXPECT_EQ(f.status, "failed");
  EXPECT_EQ(f.reason, "bmsim plan: error: bad CT (exit status 1)");
  EXPECT_EQ(bm::CohortRowFor(d, pending).status, "pending");

  // The table: a header, one record per case, empty cells for what was not measured, read back
  // by the CSV reader.
  const std::string csv = bm::CohortTableCsv({p, n, f});
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "id,ct,side,status,version_3d_deg,friedman_version_deg,inclination_deg,"
                  "glenoid_height_mm,glenoid_width_mm,correction_deg,reason");
  std::getline(in, line);
  auto fields = bm::SplitCsvRecord(line, "row 1");
  ASSERT_EQ(fields.size(), 11u);
  EXPECT_EQ(fields[0], "p");
  EXPECT_EQ(fields[4], "-11.5");
  EXPECT_EQ(fields[10], "w1; w2");
  std::getline(in, line);
  fields = bm::SplitCsvRecord(line, "row 2");
  EXPECT_EQ(fields[3], "no_glenoid");
  EXPECT_EQ(fields[4], "");
}
