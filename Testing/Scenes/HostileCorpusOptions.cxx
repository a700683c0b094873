// HostileCorpusOptions.cxx - the corpus's option cases (bmHostileCorpus.h): every numeric, point
// and word option of bmsim's commands given values out of range or not numbers.
#include "bmHostileCorpus.h"

#include <cmath>
#include <limits>
#include <sstream>

namespace bmcorpus {
namespace {

using namespace bmtest;

// ---------------------------------------------------------------------------------------------
// Options: every numeric option of every command with values out of its range or not numbers.

/// `opt` of `base` (a command line without it) in [lo, hi]; `integer`: a whole number.
void NumericOption(const std::string& cmd, const std::vector<std::string>& base,
                   const std::string& opt, double lo, double hi, bool integer) {
  const double step = std::max(1.0, std::abs(lo) * 0.5);
  std::vector<std::string> values = {"nan", Format(lo - step),
                                     Format(hi + std::max(1.0, std::abs(hi))), "1x"};
  if (integer)
    values.push_back(Format(lo + 0.5));
  for (const std::string& v : values) {
    std::vector<std::string> args = base;
    args.push_back(opt);
    args.push_back(v);
    Add(cmd + " " + opt + " '" + v + "'", args, {opt});
  }
}

/// An option taking a word from a list: an unknown word.
void WordOption(const std::string& cmd, const std::vector<std::string>& base,
                const std::string& opt) {
  for (const std::string v : {"bogus", ""}) {
    std::vector<std::string> args = base;
    args.push_back(opt);
    args.push_back(v);
    Add(cmd + " " + opt + " '" + v + "'", args, {opt});
  }
}

/// An option taking `count` comma-separated numbers.
void TupleOption(const std::string& cmd, const std::vector<std::string>& base,
                 const std::string& opt, int count) {
  auto join = [](std::vector<std::string> v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i)
      s += (i ? "," : "") + v[i];
    return s;
  };
  std::vector<std::string> ok(size_t(count), "0");
  std::vector<std::vector<std::string>> bad;
  for (const std::string x : {"nan", "inf", "x"}) {
    auto v = ok;
    v[size_t(count) - 1] = x;
    bad.push_back(v);
  }
  bad.push_back(std::vector<std::string>(size_t(count) - 1, "0")); // one number short
  bad.push_back(std::vector<std::string>(size_t(count) + 1, "0")); // one too many
  for (const auto& v : bad) {
    std::vector<std::string> args = base;
    args.push_back(opt);
    args.push_back(join(v));
    Add(cmd + " " + opt + " '" + join(v) + "'", args, {opt});
  }
}

} // namespace

void OptionCases() {
  const std::vector<std::string> run = {"run", "drilling", "--out", "{out}/r", "--no-report"};
  for (auto [opt, lo, hi, integer] : std::vector<std::tuple<std::string, double, double, bool>>{
           {"--feed", 1e-5, 1, false},
           {"--speed", 1, 100000, false},
           {"--voxmap-resolution", 8, 4096, true},
           {"--shell-resolution", 8, 4096, true},
           {"--threads", 1, 64, true},
           {"--force", 0, 3.3, false},
           {"--force-scale", 0.001, 1000, false},
           {"--seed", 0, 1e9, true},
           {"--duration", 0.001, 3600, false},
           {"--rate", 10, 10000, false},
           {"--overrun-limit", -1, 1e6, true}})
    NumericOption("run", run, opt, lo, hi, integer);
  for (const char* opt :
       {"--method", "--backend", "--lips", "--device", "--mode", "--contact", "--rendering"})
    WordOption("run", run, opt);

  const std::vector<std::string> import = {"import", "{in}/ct.nrrd", "--out", "{out}/v.nrrd", "-q"};
  for (auto [opt, lo, hi, integer] : std::vector<std::tuple<std::string, double, double, bool>>{
           {"--resolution", 8, 8192, true},
           {"--threshold", -1000, 4000, false},
           {"--raw-threshold", -1e9, 1e9, false},
           {"--max-memory", 1, 1e9, false}})
    NumericOption("import", import, opt, lo, hi, integer);
  TupleOption("import", import, "--seed", 3);
  TupleOption("import", import, "--exclude", 3);
  TupleOption("import", import, "--roi", 6);
  TupleOption("import", import, "--hu-mapping", 2);
  TupleOption("import", import, "--box", 6);
  Add("import --roi inverted",
      {"import", "{in}/ct.nrrd", "--out", "{out}/v.nrrd", "--roi", "1,1,1,0,0,0"},
      {"--roi", "inverted"});
  Add("import --box negative half size",
      {"import", "{in}/ct.nrrd", "--out", "{out}/v.nrrd", "--box", "0,0,0,-1,1,1"}, {"--box"});
  Add("import --hu-mapping zero slope",
      {"import", "{in}/ct.nrrd", "--out", "{out}/v.nrrd", "--hu-mapping", "0,5"}, {"--hu-mapping"});

  const std::vector<std::string> plan = {"plan", "phantom", "--out", "{out}/p", "-q"};
  for (auto [opt, lo, hi, integer] : std::vector<std::tuple<std::string, double, double, bool>>{
           {"--target-version", -44.9, 44.9, false},
           {"--target-inclination", -44.9, 44.9, false},
           {"--reamer-diameter", 10, 60, false},
           {"--ream-depth", 0.01, 10, false},
           {"--pin-radius", 0.01, 5, false},
           {"--pin-depth", 0.01, 40, false},
           {"--resolution", 32, 1024, true},
           {"--threshold", -1000, 4000, false},
           {"--phantom-version", -45, 45, false},
           {"--phantom-inclination", -45, 45, false},
           {"--raw-threshold", -1e9, 1e9, false},
           {"--max-memory", 1, 1e9, false}})
    NumericOption("plan", plan, opt, lo, hi, integer);
  for (auto [opt, n] : std::vector<std::pair<std::string, int>>{
           {"--seed", 3}, {"--exclude", 3}, {"--roi", 6}, {"--hu-mapping", 2}, {"--box", 6}})
    TupleOption("plan", plan, opt, n);
  WordOption("plan", plan, "--side");

  const std::vector<std::string> bench = {"bench", "--out", "{out}/b"};
  for (auto [opt, lo, hi, integer] :
       std::vector<std::tuple<std::string, double, double, bool>>{{"--frames", 1, 1e8, true},
                                                                  {"--warmup", 0, 1e6, true},
                                                                  {"--threads", 1, 64, true},
                                                                  {"--cell-limit", 1, 86400, false},
                                                                  {"--interval", 0, 10000, false},
                                                                  {"--repeats", 1, 100, true},
                                                                  {"--budget", 0, 10000, false},
                                                                  {"--brick", 2, 256, true},
                                                                  {"--serial", 0, 1e6, true},
                                                                  {"--seconds", 0.01, 3600, false},
                                                                  {"--push", 0.01, 3.3, false},
                                                                  {"--tremor", 0, 3.3, false}})
    NumericOption("bench", bench, opt, lo, hi, integer);
  for (const char* opt : {"--shells", "--voxmaps"})
    for (const std::string v : {"nan", "7", "5000", "128,x", "1e999"}) {
      auto args = bench;
      args.insert(args.end(), {opt, v});
      Add(std::string("bench ") + opt + " '" + v + "'", args, {opt});
    }
  for (const char* opt : {"--methods", "--backends"}) {
    auto args = bench;
    args.insert(args.end(), {opt, "bogus"});
    Add(std::string("bench ") + opt + " bogus", args, {opt});
  }

  const std::vector<std::string> phantom = {"phantom", "block", "--out", "{out}/ph", "-q"};
  for (auto [opt, lo, hi, integer] :
       std::vector<std::tuple<std::string, double, double, bool>>{{"--noise", 0, 1000, false},
                                                                  {"--blur", 0, 10, false},
                                                                  {"--version", -45, 45, false},
                                                                  {"--inclination", -45, 45, false},
                                                                  {"--pixel-mm", 0.3, 3, false},
                                                                  {"--slice-mm", 0.5, 5, false},
                                                                  {"--joint-gap", 1, 20, false}})
    NumericOption("phantom", phantom, opt, lo, hi, integer);
  WordOption("phantom", phantom, "--compress");
  const std::vector<std::string> scapula = {"phantom", "scapula", "--out", "{out}/ph", "-q"};
  TupleOption("phantom scapula", scapula, "--window", 2);
  Add("phantom scapula --window zero width",
      {"phantom", "scapula", "--out", "{out}/ph", "-q", "--window", "400,0"}, {"--window"});
  Add("phantom scapula --window with --compress",
      {"phantom", "scapula", "--out", "{out}/ph", "-q", "--window", "400,2000", "--compress",
       "rle"},
      {"--compress"});

  NumericOption("replay", {"replay", "{in}/r.csv", "--out", "{out}/rp"}, "--tolerance", 0, 1e6,
                false);
  const std::vector<std::string> calibrate = {"calibrate", "{in}/d.csv", "--out", "{out}/c"};
  WordOption("calibrate", calibrate, "--bone-factors");
  WordOption("calibrate", calibrate, "--chisel");
  Add("calibrate --basis bogus", {"calibrate", "{in}/d.csv", "--out", "{out}/c", "--basis", "x"},
      {"basis"}, [](const fs::path& in) {
        WriteFile(in / "d.csv", "tool,feed_mm_per_rev,speed_rpm,thrust_N\ndrill,0.02,1000,5\n");
      });
}

} // namespace bmcorpus
