// bmsimArgs.h - options of a bmsim subcommand: positional words and "--name value" / "--flag".
//
// Unknown options, missing values and malformed numbers raise bm::cli::UsageError naming the
// option, so every command refuses bad input before it writes anything.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "bmsimCommand.h"

namespace bm::cli {

class ParsedArgs {
public:
  /// valued: options that take a value; flags: options that do not (both without "--");
  /// shortNames: one-letter spellings, e.g. {"o", "out"} makes "-o FILE" mean "--out FILE"
  /// (default none); usage: text appended, after a newline, to every error the parsing raises
  /// (default none). A word of a dash and a letter that is no short name is an unknown option;
  /// other words (a negative number too) are positional.
  ParsedArgs(const Args& args, const std::set<std::string>& valued,
             const std::set<std::string>& flags = {},
             const std::map<std::string, std::string>& shortNames = {},
             const std::string& usage = "");

  const std::vector<std::string>& Positional() const { return Positional_; }
  bool Has(const std::string& name) const { return Values_.count(name) || Flags_.count(name); }
  std::optional<std::string> Get(const std::string& name) const;
  std::string Get(const std::string& name, const std::string& def) const;
  /// Integer option within [lo, hi].
  std::optional<long> GetInt(const std::string& name, long lo, long hi) const;
  /// Finite number option within [lo, hi] (-HUGE_VAL, HUGE_VAL: any).
  std::optional<double> GetDouble(const std::string& name, double lo, double hi) const;
  /// Comma-separated numbers, exactly `count` of them.
  std::optional<std::vector<double>> GetDoubles(const std::string& name, size_t count) const;

private:
  std::vector<std::string> Positional_;
  std::map<std::string, std::string> Values_;
  std::set<std::string> Flags_;
};

} // namespace bm::cli
