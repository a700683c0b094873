// bm::SplitCsvRecord and bm::ParseCsvNumbers: the CSV helper every reader uses.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "bmCsv.h"

namespace {

TEST(Csv, FieldsQuotesBlanksAndTheEmptyLastField) {
  using V = std::vector<std::string>;
  EXPECT_EQ(bm::SplitCsvRecord("a,b,c", "w"), (V{"a", "b", "c"}));
  EXPECT_EQ(bm::SplitCsvRecord(" 1 , 2\r", "w"), (V{"1", "2"}));
  EXPECT_EQ(bm::SplitCsvRecord("\"Lee, 2012\",\"say \"\"hi\"\"\",x", "w"),
            (V{"Lee, 2012", "say \"hi\"", "x"}));
  EXPECT_EQ(bm::SplitCsvRecord("a,b,", "w"), (V{"a", "b", ""}));
  EXPECT_EQ(bm::SplitCsvRecord("", "w"), (V{""}));
  try {
    bm::SplitCsvRecord("\"open,b", "f.csv:3");
    FAIL() << "an unterminated quote was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "f.csv:3: unterminated quote");
  }
}

TEST(Csv, NumbersAreWholeFieldsOrRefusedNamingTheField) {
  const std::vector<double> v = bm::ParseCsvNumbers("1.5, -2e-3,7", "w");
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0], 1.5);
  EXPECT_EQ(v[1], -2e-3);
  EXPECT_EQ(v[2], 7.0);
  EXPECT_TRUE(std::isnan(bm::ParseCsvNumbers("nan", "w")[0])); // the reader decides on NaN
  for (const char* bad : {"1x,2", "1,,2", "1,2,", "abc"}) {
    try {
      bm::ParseCsvNumbers(bad, "t.csv:4");
      FAIL() << "accepted '" << bad << "'";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("t.csv:4: not a number: '", 0), 0u) << e.what();
    }
  }
}

} // namespace
