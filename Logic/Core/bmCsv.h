// bmCsv.h - reading CSV records, the one helper every CSV reader uses (calibration data, bench
// tables, trajectories, session recordings), and quoting a text field for the writers.
#pragma once

#include <string>
#include <vector>

namespace bm {

/// Splits one CSV record at its commas. A field may be quoted ("a, b"; a doubled quote inside is
/// one quote); blanks around unquoted fields and a trailing '\r' are dropped. "a,b," has three
/// fields, the last empty. Throws std::invalid_argument "WHERE: unterminated quote".
std::vector<std::string> SplitCsvRecord(const std::string& line, const std::string& where);

/// The record's fields as numbers (each field wholly a number: "1.5", "-2e-3", "nan"; "1x" and ""
/// are not). Throws std::runtime_error "WHERE: not a number: 'FIELD'".
std::vector<double> ParseCsvNumbers(const std::string& line, const std::string& where);

/// A header record: the column names joined by commas.
template <class Names> std::string CsvHeader(const Names& names) {
  std::string h;
  for (const char* name : names) {
    if (!h.empty())
      h += ',';
    h += name;
  }
  return h;
}

/// `s` as a quoted CSV field ("a, b"; a quote inside doubled), as SplitCsvRecord reads it back.
std::string CsvQuoted(const std::string& s);

} // namespace bm
