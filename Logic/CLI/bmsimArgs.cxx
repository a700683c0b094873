#include "bmsimArgs.h"

#include <cctype>
#include <cmath>
#include <sstream>

namespace bm::cli {

ParsedArgs::ParsedArgs(const Args& args, const std::set<std::string>& valued,
                       const std::set<std::string>& flags,
                       const std::map<std::string, std::string>& shortNames,
                       const std::string& usage) {
  auto fail = [&](const std::string& what) {
    throw UsageError(usage.empty() ? what : what + "\n" + usage);
  };
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    std::string name, value;
    bool hasInline = false;
    if (a.rfind("--", 0) == 0) {
      name = a.substr(2);
      const auto eq = name.find('=');
      hasInline = eq != std::string::npos;
      if (hasInline) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
      }
    } else if (a.size() >= 2 && a[0] == '-' && std::isalpha(static_cast<unsigned char>(a[1]))) {
      const auto it = shortNames.find(a.substr(1));
      if (it == shortNames.end())
        fail("unknown option " + a);
      name = it->second;
    } else {
      Positional_.push_back(a);
      continue;
    }
    if (flags.count(name)) {
      if (hasInline)
        fail("option --" + name + " takes no value");
      Flags_.insert(name);
    } else if (valued.count(name)) {
      if (!hasInline) {
        if (i + 1 >= args.size())
          fail(a + " needs a value");
        value = args[++i];
      }
      Values_[name] = value;
    } else {
      fail("unknown option --" + name);
    }
  }
}

std::optional<std::string> ParsedArgs::Get(const std::string& name) const {
  auto it = Values_.find(name);
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
  if (x < lo || x > hi) {
    std::ostringstream os;
    os << "--" << name << " must be in [" << lo << ", " << hi << "], got " << *v;
    throw UsageError(os.str());
  }
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
