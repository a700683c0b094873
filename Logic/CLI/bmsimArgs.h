// bmsimArgs.h - the options of a bmsim subcommand, declared to CLI11 (which parses them, refuses
// unknown options, missing values and values out of range naming the option and the range, and
// writes --help) and read by name once parsed.
//
// Declaring: names are "out" (--out) or "o,out" (-o and --out). A number option's range shows in
// --help and is checked by the parser; GetInt/GetDouble check a (narrower) range again where a
// command's mode needs one.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bmsimCommand.h"

namespace CLI {
class App;
class Option;
} // namespace CLI

namespace bm::cli {

class ParsedArgs {
public:
  /// Options declared on `app` (a subcommand of bmsim), which must outlive this object.
  explicit ParsedArgs(CLI::App& app);

  ///@{
  /// Declarations, before parsing. type: the value's name in --help (e.g. "DIR", "HU").
  ParsedArgs& Value(const std::string& names, const std::string& type, const std::string& help);
  /// An integer in [lo, hi].
  ParsedArgs& Int(const std::string& names, long lo, long hi, const std::string& help);
  /// A finite number in [lo, hi].
  ParsedArgs& Real(const std::string& names, double lo, double hi, const std::string& type,
                   const std::string& help);
  /// One of `choices`.
  ParsedArgs& Choice(const std::string& names, const std::vector<std::string>& choices,
                     const std::string& help);
  /// A flag (no value).
  ParsedArgs& Flag(const std::string& names, const std::string& help);
  /// The positional words (any number; the command checks how many it needs).
  ParsedArgs& Words(const std::string& name, const std::string& help);
  /// Text after the options in --help.
  ParsedArgs& Footer(const std::string& text);
  ///@}

  const std::vector<std::string>& Positional() const { return Positional_; }
  /// Whether the option (long name, without "--") was given.
  bool Has(const std::string& name) const;
  std::optional<std::string> Get(const std::string& name) const;
  std::string Get(const std::string& name, const std::string& def) const;
  /// Integer option within [lo, hi]; throws UsageError naming the option and the range.
  std::optional<long> GetInt(const std::string& name, long lo, long hi) const;
  /// Finite number option within [lo, hi] (-HUGE_VAL, HUGE_VAL: any).
  std::optional<double> GetDouble(const std::string& name, double lo, double hi) const;
  /// Comma-separated numbers, exactly `count` of them.
  std::optional<std::vector<double>> GetDoubles(const std::string& name, size_t count) const;

private:
  CLI::Option* Add(const std::string& names, const std::string& help, bool flag);

  CLI::App& App_;
  std::vector<std::string> Positional_;
  std::map<std::string, std::string> Values_;
  std::map<std::string, CLI::Option*> Options_;
};

} // namespace bm::cli
