// bmsimArgs.cxx - see bmsimArgs.h.
#include "bmsimArgs.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <sstream>

namespace bm::cli {

namespace {

/// "o,out" -> {"-o,--out", "out"}; "out" -> {"--out", "out"}.
std::pair<std::string, std::string> CliNames(const std::string& names) {
  const auto comma = names.find(',');
  if (comma == std::string::npos)
    return {"--" + names, names};
  const std::string s = names.substr(0, comma), l = names.substr(comma + 1);
  return {"-" + s + ",--" + l, l};
}

std::string Num(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

/// A number in [lo, hi] (an integer when `integer`): the message names the range and the value.
CLI::Validator InRange(double lo, double hi, bool integer) {
  const std::string range = "in [" + Num(lo) + ", " + Num(hi) + "]";
  return CLI::Validator(
      [=](std::string& v) -> std::string {
        size_t pos = 0;
        double x = 0;
        try {
          x = integer ? double(std::stol(v, &pos)) : std::stod(v, &pos);
        } catch (const std::exception&) {
          pos = 0;
        }
        if (pos == 0 || pos != v.size() || !std::isfinite(x))
          return std::string(integer ? "needs an integer" : "needs a number") + " " + range +
                 ", got '" + v + "'";
        if (x < lo || x > hi)
          return "must be " + range + ", got " + v;
        return std::string();
      },
      range);
}

} // namespace

ParsedArgs::ParsedArgs(CLI::App& app) : App_(app) {}

CLI::Option* ParsedArgs::Add(const std::string& names, const std::string& help, bool flag) {
  const auto [cli, name] = CliNames(names);
  CLI::Option* o = flag ? App_.add_flag(cli, help) : App_.add_option(cli, Values_[name], help);
  Options_[name] = o;
  return o;
}

ParsedArgs& ParsedArgs::Value(const std::string& names, const std::string& type,
                              const std::string& help) {
  Add(names, help, false)->type_name(type);
  return *this;
}

ParsedArgs& ParsedArgs::Int(const std::string& names, long lo, long hi, const std::string& help) {
  Add(names, help, false)->type_name("INT")->check(InRange(double(lo), double(hi), true));
  return *this;
}

ParsedArgs& ParsedArgs::Real(const std::string& names, double lo, double hi,
                             const std::string& type, const std::string& help) {
  CLI::Option* o = Add(names, help, false)->type_name(type);
  if (std::isfinite(lo) || std::isfinite(hi))
    o->check(InRange(lo, hi, false));
  return *this;
}

ParsedArgs& ParsedArgs::Choice(const std::string& names, const std::vector<std::string>& choices,
                               const std::string& help) {
  Add(names, help, false)->type_name("WORD")->check(CLI::IsMember(choices));
  return *this;
}

ParsedArgs& ParsedArgs::Flag(const std::string& names, const std::string& help) {
  Add(names, help, true);
  return *this;
}

ParsedArgs& ParsedArgs::Words(const std::string& name, const std::string& help) {
  App_.add_option(name, Positional_, help)->expected(0, -1);
  return *this;
}

ParsedArgs& ParsedArgs::Footer(const std::string& text) {
  App_.footer(text + "\n");
  return *this;
}

bool ParsedArgs::Has(const std::string& name) const {
  const auto it = Options_.find(name);
  return it != Options_.end() && it->second->count() > 0;
}

std::optional<std::string> ParsedArgs::Get(const std::string& name) const {
  if (!Has(name))
    return std::nullopt;
  const auto it = Values_.find(name);
  if (it == Values_.end())
    return std::nullopt;
  return it->second;
}

std::string ParsedArgs::Get(const std::string& name, const std::string& def) const {
  return Get(name).value_or(def);
}

std::optional<long> ParsedArgs::GetInt(const std::string& name, long lo, long hi) const {
  auto v = Get(name);
  if (!v)
    return std::nullopt;
  size_t pos = 0;
  long x = 0;
  try {
    x = std::stol(*v, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  if (pos == 0 || pos != v->size())
    throw UsageError("--" + name + " needs an integer, got '" + *v + "'");
  if (x < lo || x > hi)
    throw UsageError("--" + name + " must be in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "], got " + *v);
  return x;
}

std::optional<double> ParsedArgs::GetDouble(const std::string& name, double lo, double hi) const {
  auto v = Get(name);
  if (!v)
    return std::nullopt;
  size_t pos = 0;
  double x = 0;
  try {
    x = std::stod(*v, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  if (pos == 0 || pos != v->size() || !std::isfinite(x))
    throw UsageError("--" + name + " needs a number, got '" + *v + "'");
  if (x < lo || x > hi)
    throw UsageError("--" + name + " must be in [" + Num(lo) + ", " + Num(hi) + "], got " + *v);
  return x;
}

std::optional<std::vector<double>> ParsedArgs::GetDoubles(const std::string& name,
                                                          size_t count) const {
  auto v = Get(name);
  if (!v)
    return std::nullopt;
  std::vector<double> out;
  std::stringstream ss(*v);
  std::string item;
  while (std::getline(ss, item, ',')) {
    size_t pos = 0;
    double x = 0;
    try {
      x = std::stod(item, &pos);
    } catch (const std::exception&) {
      pos = 0;
    }
    if (pos == 0 || pos != item.size() || !std::isfinite(x))
      throw UsageError("--" + name + " needs " + std::to_string(count) +
                       " comma-separated numbers, got '" + *v + "'");
    out.push_back(x);
  }
  if (out.size() != count)
    throw UsageError("--" + name + " needs " + std::to_string(count) +
                     " comma-separated numbers, got '" + *v + "'");
  return out;
}

} // namespace bm::cli
