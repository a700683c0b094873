// HostileCorpusTables.cxx - the corpus's cases for the tables bmsim reads (bmHostileCorpus.h):
// calibration data, coefficient sets, benchmark tables and landmarks, damaged.
#include "bmHostileCorpus.h"

#include <sys/stat.h>

#include <string>
#include <vector>

namespace bmcorpus {

using namespace bmtest;

void TableCases() {
  // Calibration data.
  auto calibration = [](const std::string& name, const std::vector<std::string>& needles,
                        const std::string& text) {
    Add("calibrate " + name, {"calibrate", "{in}/" + name, "--out", "{out}/c"}, needles,
        Writes(name, text));
  };
  const std::string head = "tool,feed_mm_per_rev,speed_rpm,thrust_N,torque_Nmm\n";
  const std::string ok = "drill,0.02,1000,5,10\n";
  calibration("nan-feed.csv", {"nan-feed.csv:3", "feed_mm_per_rev"},
              head + ok + "drill,nan,1000,5,10\n");
  calibration("inf-thrust.csv", {"inf-thrust.csv:3", "thrust_N"},
              head + ok + "drill,0.02,1000,inf,10\n");
  calibration("word-speed.csv", {"word-speed.csv:3", "speed_rpm"},
              head + ok + "drill,0.02,fast,5,10\n");
  calibration("neg-feed.csv", {"neg-feed.csv:3", "feed"}, head + ok + "drill,-0.02,1000,5,10\n");
  calibration("zero-speed.csv", {"zero-speed.csv:3", "speed"}, head + ok + "drill,0.02,0,5,10\n");
  calibration("huge-thrust.csv", {"huge-thrust.csv:3", "thrust"},
              head + ok + "drill,0.02,1000,1e300,10\n");
  calibration("tool.csv", {"tool.csv:3", "hammer"}, head + ok + "hammer,0.02,1000,5,10\n");
  calibration("no-tool.csv", {"no-tool.csv", "tool"},
              "feed_mm_per_rev,speed_rpm,thrust_N\n0.02,1000,5\n");
  calibration("columns.csv", {"columns.csv:3"}, head + ok + "drill,0.02\n");
  calibration("empty.csv", {"empty.csv"}, "");
  calibration("header-only.csv", {"header-only.csv"}, head);
  calibration("quote.csv", {"quote.csv:3"}, head + ok + "\"drill,0.02,1000,5,10\n");
  calibration("diameter.csv", {"diameter.csv:3", "diameter"},
              "tool,diameter_mm,feed_mm_per_rev,speed_rpm,thrust_N\ndrill,2.5,0.02,1000,5\n"
              "drill,-1,0.02,1000,5\n");
  Add("calibrate FIFO", {"calibrate", "{in}/fifo.csv", "--out", "{out}/c"}, {"fifo.csv"},
      [](const fs::path& in) { ::mkfifo((in / "fifo.csv").c_str(), 0600); });

  // Benchmark tables given to --replot.
  auto bench = [](const std::string& name, const std::vector<std::string>& needles,
                  const std::string& text) {
    Add("bench --replot " + name, {"bench", "--replot", "{in}/" + name, "--out", "{out}/b"},
        needles, Writes(name, text));
  };
  const std::string bh = "method,backend,shell,voxmap,status,median_ms,p99_ms,force_error\n";
  bench("no-shell.csv", {"no-shell.csv", "shell"}, "method,backend\nlazar,cpu\n");
  bench("nan-median.csv", {"nan-median.csv:2", "median_ms"}, bh + "lazar,cpu,128,128,ok,nan,1,0\n");
  bench("word-shell.csv", {"word-shell.csv:2", "shell"}, bh + "lazar,cpu,x,128,ok,1,1,0\n");
  bench("method.csv", {"method.csv:2", "method"}, bh + "bogus,cpu,128,128,ok,1,1,0\n");
  bench("half-shell.csv", {"half-shell.csv:2", "shell", "8..4096"},
        bh + "lazar,cpu,128.5,128,ok,1,1,0\n");
  bench("huge-voxmap.csv", {"huge-voxmap.csv:2", "voxmap", "8..4096"},
        bh + "lazar,cpu,128,1e300,ok,1,1,0\n");
  bench("columns.csv", {"columns.csv:2"}, bh + "lazar,cpu\n");
  bench("empty.csv", {"empty.csv"}, "");
  bench("deep-result.csv", {"deep-result.csv"},
        "method,backend,shell,voxmap,status,result\nlazar,cpu,128,128,ok,\"" +
            std::string(100000, '[') + "\"\n");
  Add("bench --replot missing", {"bench", "--replot", "{in}/none.csv", "--out", "{out}/b"},
      {"none.csv"});
  Add("bench --replot FIFO", {"bench", "--replot", "{in}/fifo.csv", "--out", "{out}/b"},
      {"fifo.csv"}, [](const fs::path& in) { ::mkfifo((in / "fifo.csv").c_str(), 0600); });

  // Landmarks of bmsim plan.
  auto landmarks = [](const std::string& name, const std::vector<std::string>& needles,
                      const std::string& json) {
    Add("plan --landmarks " + name,
        {"plan", "phantom", "--out", "{out}/p", "-q", "--landmarks", "{in}/" + name}, needles,
        Writes(name, json));
  };
  const std::string good = "\"face_normal\": [0, 0, 1], \"trigonum_mm\": [0, 50, 0], "
                           "\"inferior_angle_mm\": [0, 0, -100]";
  std::string deep(100000, '[');
  deep += std::string(100000, ']');
  landmarks("deep.json", {"nested deeper than 64 levels"}, deep);
  landmarks("syntax.json", {"syntax.json"}, "{");
  landmarks("array.json", {"must be an object"}, "[1]");
  landmarks("centre-text.json", {"glenoid_centre_mm"},
            "{\"glenoid_centre_mm\": [1, 2, \"x\"], " + good + "}");
  landmarks("centre-short.json", {"glenoid_centre_mm"},
            "{\"glenoid_centre_mm\": [1, 2], " + good + "}");
  Add("plan --landmarks FIFO",
      {"plan", "phantom", "--out", "{out}/p", "-q", "--landmarks", "{in}/fifo.json"}, {"fifo.json"},
      [](const fs::path& in) { ::mkfifo((in / "fifo.json").c_str(), 0600); });
  Add("plan hostile CT", {"plan", "{in}/ct.nrrd", "--out", "{out}/p", "-q"},
      {"non-finite voxel spacing"}, Writes("ct.nrrd", Nrrd({{"spacings", "nan 1 1"}})));
  Add("plan --out is a file", {"plan", "phantom", "--out", "{in}/file", "-q"}, {"--out"},
      Writes("file", "x"));
}

} // namespace bmcorpus
