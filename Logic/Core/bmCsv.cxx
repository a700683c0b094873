// bmCsv.cxx - see bmCsv.h.
#include "bmCsv.h"

#include <cstdlib>
#include <stdexcept>

namespace bm {

std::vector<std::string> SplitCsvRecord(const std::string& line, const std::string& where) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false, wasQuoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cur += c;
      }
    } else if (c == '"' && cur.find_first_not_of(" \t") == std::string::npos && !wasQuoted) {
      cur.clear();
      quoted = wasQuoted = true;
    } else if (c == ',') {
      out.push_back(cur);
      cur.clear();
      wasQuoted = false;
    } else if (c != '\r') {
      cur += c;
    }
  }
  if (quoted)
    throw std::invalid_argument(where + ": unterminated quote");
  out.push_back(cur);
  for (auto& f : out) { // trim blanks around unquoted numbers and words
    const size_t a = f.find_first_not_of(" \t"), b = f.find_last_not_of(" \t");
    f = a == std::string::npos ? "" : f.substr(a, b - a + 1);
  }
  return out;
}

std::vector<double> ParseCsvNumbers(const std::string& line, const std::string& where) {
  std::vector<double> out;
  for (const std::string& f : SplitCsvRecord(line, where)) {
    const char* begin = f.c_str();
    char* end = nullptr;
    const double v = f.empty() ? 0.0 : std::strtod(begin, &end);
    if (f.empty() || end != begin + f.size())
      throw std::runtime_error(where + ": not a number: '" + f + "'");
    out.push_back(v);
  }
  return out;
}

std::string CsvQuoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s)
    q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

} // namespace bm
