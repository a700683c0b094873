#include "bmBenchmark.h"

#include <algorithm>
#include <charconv>
#include <climits>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <iomanip>
#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <type_traits>

#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "bmEdgeQuadrature.h"
#include "bmFeedTrial.h"
#include "bmMachiningSetup.h"
#include "bmToolModel.h"
#include "bmCsv.h"
#include "bmJson.h"

#include <Eigen/Geometry>

namespace bm {

Scene BenchScene(Method method, const std::string& backend, int shell, int voxmap, int threads) {
  Scene s = Scene::Builtin("drilling");
  s.method = method;
  s.forceModel = nlohmann::json();
  s.backend = backend;
  s.shellResolution = shell;
  s.voxmapResolution = voxmap;
  s.threads = threads;
  s.Validate();
  return s;
}

namespace {

// Sets to void every voxel whose centre lies in the envelope the tool swept on its way down the
// trial axis until its foremost cutting point is `depth` below the entry point, less a layer
// `marginMm` thick above the tool's lower surface: the voxels the shell's elements sit in keep
// their bone, as they would in steady drilling, where the lips cut the layer in front of them.
// Only the voxels of the envelope's bounding box are tested (a box grown by a voxel: the test
// below decides every voxel as it would over the whole grid), slices split over threads: at
// voxmap 1024^3 the whole grid took 15 s of a cell's set-up.
void PreCut(const Scene& s, Voxmap& bone, double depth, double marginMm) {
  const auto tool = MakeTool(s.tool);
  const Eigen::Vector3d axis = s.trial.axis.normalized();
  const Eigen::Matrix3d rot =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix();
  const double zf = ForemostCuttingZ(*tool);
  const Eigen::Vector3d origin = s.trial.entry - axis * depth - rot * Eigen::Vector3d(0, 0, zf);
  const double R = tool->OuterRadius();
  const auto dims = bone.Dims();
  // The envelope lies within rho <= R, z >= the tool's lowest point, up to past the grid's far
  // corner: its world bounding box, in voxel indices.
  const Box3 b = bone.Bounds();
  double reach = 0;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d corner((c & 1) ? b.hi[0] : b.lo[0], (c & 2) ? b.hi[1] : b.lo[1],
                                 (c & 4) ? b.hi[2] : b.lo[2]);
    reach = std::max(reach, (corner - origin).norm());
  }
  const double zLow = tool->AxialRange()[0];
  std::array<int, 3> lo{INT_MAX, INT_MAX, INT_MAX}, hi{INT_MIN, INT_MIN, INT_MIN};
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d w = origin + rot * Eigen::Vector3d((c & 1) ? R : -R, (c & 2) ? R : -R,
                                                             (c & 4) ? zLow + reach + R : zLow);
    const auto g = bone.WorldToGrid({w(0), w(1), w(2)});
    for (int a = 0; a < 3; ++a) {
      lo[size_t(a)] = std::min(lo[size_t(a)], int(std::floor(g[size_t(a)])) - 1);
      hi[size_t(a)] = std::max(hi[size_t(a)], int(std::ceil(g[size_t(a)])) + 1);
    }
  }
  for (int a = 0; a < 3; ++a) {
    lo[size_t(a)] = std::max(lo[size_t(a)], 0);
    hi[size_t(a)] = std::min(hi[size_t(a)], dims[size_t(a)] - 1);
    if (lo[size_t(a)] > hi[size_t(a)])
      return;
  }
  Voxmap::Fill* fill = bone.MutableFill();
  auto slices = [&](int k0, int k1) {
    for (int k = k0; k < k1; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const auto w = bone.GridToWorld({double(i), double(j), double(k)});
          const Eigen::Vector3d p = rot.transpose() * (Eigen::Vector3d(w[0], w[1], w[2]) - origin);
          const double rho = std::hypot(p(0), p(1));
          if (rho > R)
            continue;
          double zLo = 0, zHi = 0;
          if (tool->ZRange(rho, zLo, zHi) && p(2) >= zLo + marginMm)
            fill[bone.Index(i, j, k)] = 0;
        }
  };
  const int n = hi[2] - lo[2] + 1;
  const int T = std::clamp(int(std::thread::hardware_concurrency()), 1, std::max(1, n / 8));
  std::vector<std::thread> workers;
  for (int t = 1; t < T; ++t)
    workers.emplace_back(slices, lo[2] + n * t / T, lo[2] + n * (t + 1) / T);
  slices(lo[2], lo[2] + n / T);
  for (auto& w : workers)
    w.join();
  bone.RebuildOccupancy();
}

} // namespace

BenchCell RunBenchCell(Method method, const std::string& backend, int shell, int voxmap,
                       const BenchOptions& o) {
  BenchCell c;
  c.method = method;
  c.backend = backend;
  c.shell = shell;
  c.voxmap = voxmap;
  const auto t0 = std::chrono::steady_clock::now();
  const Scene scene = BenchScene(method, backend, shell, voxmap, o.threads);
  // Start past full engagement of the edges by four voxels and 0.1 mm (more than the coarsest
  // shell spacing, 10 mm / 128), so every timed frame is fully engaged.
  Voxmap block = MakeSceneBlock(scene);
  const double start = FullEngagementDepth(*MakeTool(scene.tool)) + 4 * block.Spacing() + 0.1;
  {
    // An element lies within half a shell cell of the surface and its voxel centre within half
    // a voxel diagonal of it: keep one shell spacing plus one voxel diagonal of bone.
    const auto tool = MakeTool(scene.tool);
    const auto zr = tool->AxialRange();
    const double hs = std::max(2 * tool->OuterRadius(), zr[1] - zr[0]) / shell;
    PreCut(scene, block, start, hs + std::sqrt(3.0) * block.Spacing());
  }
  MachiningSetup setup(scene, std::move(block), o.device, o.deviceHeldBone);
  c.setupS = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  c.engine = setup.GetEngine().Name();
  c.elements = int64_t(setup.Shell().Size());

  const FeedPath path(setup);
  const double step = path.StepMm();
  Engine& engine = setup.GetEngine();
  std::vector<double> ms;
  ms.reserve(size_t(o.frames));
  double thrust = 0, torque = 0, engaged = 0;
  for (int k = 0; k < o.warmup + o.frames; ++k) {
    const FrameInput in = path.Frame(start + step * double(k + 1), k);
    const auto a = std::chrono::steady_clock::now();
    const FrameResult r = engine.Step(in);
    const auto b = std::chrono::steady_clock::now();
    if (k < o.warmup)
      continue;
    ms.push_back(std::chrono::duration<double, std::milli>(b - a).count());
    thrust += r.thrustN;
    torque += r.torqueNmm;
    engaged += double(r.engagedCutting);
  }
  c.frames = o.frames;
  c.thrustN = thrust / o.frames;
  c.torqueNmm = torque / o.frames;
  c.engagedCutting = engaged / o.frames;
  c.medianMs = Percentile(ms, 50);
  c.p99Ms = Percentile(ms, 99);
  c.maxMs = *std::max_element(ms.begin(), ms.end());
  c.meanMs = std::accumulate(ms.begin(), ms.end(), 0.0) / double(ms.size());
  double var = 0;
  for (double v : ms)
    var += (v - c.meanMs) * (v - c.meanMs);
  c.sdMs = std::sqrt(var / double(ms.size()));
  const EdgeIntegral ref =
      IntegrateEdges(setup.Tool(), setup.Model(), scene.trial.feedMmPerRev, scene.trial.speedRpm);
  c.refThrustN = ref.thrustN;
  c.refTorqueNmm = ref.torqueNmm;
  c.thrustError = std::abs(c.thrustN - ref.thrustN) / std::abs(ref.thrustN);
  c.torqueError = std::abs(c.torqueNmm - ref.torqueNmm) / std::abs(ref.torqueNmm);
  c.forceError = std::max(c.thrustError, c.torqueError);
  c.coefficients = setup.Model().Provenance().name;
  c.calibrated = setup.Model().Provenance().calibrated;
  return c;
}

namespace {

nlohmann::json ToJson(const BenchCell& c) {
  return {{"status", c.status},
          {"engine", c.engine},
          {"elements", c.elements},
          {"frames", c.frames},
          {"median", c.medianMs},
          {"p99", c.p99Ms},
          {"mean", c.meanMs},
          {"sd", c.sdMs},
          {"max", c.maxMs},
          {"thrust", c.thrustN},
          {"torque", c.torqueNmm},
          {"refThrust", c.refThrustN},
          {"refTorque", c.refTorqueNmm},
          {"thrustErr", c.thrustError},
          {"torqueErr", c.torqueError},
          {"forceErr", c.forceError},
          {"engaged", c.engagedCutting},
          {"setup", c.setupS},
          {"coefficients", c.coefficients},
          {"calibrated", c.calibrated}};
}

void FromJson(const nlohmann::json& j, BenchCell& c) {
  c.status = j.at("status");
  c.engine = j.at("engine");
  c.elements = j.at("elements");
  c.frames = j.at("frames");
  c.medianMs = j.at("median");
  c.p99Ms = j.at("p99");
  c.meanMs = j.at("mean");
  c.sdMs = j.at("sd");
  c.maxMs = j.at("max");
  c.thrustN = j.at("thrust");
  c.torqueNmm = j.at("torque");
  c.refThrustN = j.at("refThrust");
  c.refTorqueNmm = j.at("refTorque");
  c.thrustError = j.at("thrustErr");
  c.torqueError = j.at("torqueErr");
  c.forceError = j.at("forceErr");
  c.engagedCutting = j.at("engaged");
  c.setupS = j.at("setup");
  c.coefficients = j.at("coefficients");
  c.calibrated = j.at("calibrated");
}

} // namespace

BenchCell RunBenchCellIsolated(Method method, const std::string& backend, int shell, int voxmap,
                               const BenchOptions& o) {
  BenchCell c;
  c.method = method;
  c.backend = backend;
  c.shell = shell;
  c.voxmap = voxmap;
  int fds[2];
  if (pipe(fds) != 0)
    throw std::runtime_error("bench: pipe failed");
  const pid_t pid = fork();
  if (pid < 0)
    throw std::runtime_error("bench: fork failed");
  if (pid == 0) {
    close(fds[0]);
    std::string out;
    try {
      out = ToJson(RunBenchCell(method, backend, shell, voxmap, o)).dump();
    } catch (const std::exception& e) {
      BenchCell failed;
      failed.status = std::string("failed: ") + e.what();
      out = ToJson(failed).dump();
    }
    size_t done = 0;
    while (done < out.size()) {
      const ssize_t w = write(fds[1], out.data() + done, out.size() - done);
      if (w <= 0)
        break;
      done += size_t(w);
    }
    close(fds[1]);
    _exit(0);
  }
  close(fds[1]);
  std::string text;
  char buf[4096];
  const auto t0 = std::chrono::steady_clock::now();
  bool timedOut = false;
  for (;;) {
    pollfd p{fds[0], POLLIN, 0};
    const double left =
        o.cellLimitS - std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (left <= 0) {
      timedOut = true;
      kill(pid, SIGKILL);
      break;
    }
    const int ready = poll(&p, 1, int(std::min(left, 1.0) * 1000) + 1);
    if (ready <= 0)
      continue;
    const ssize_t r = read(fds[0], buf, sizeof buf);
    if (r <= 0)
      break;
    text.append(buf, size_t(r));
  }
  close(fds[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  c.peakMemoryMb = double(usage.ru_maxrss) / 1024.0;
  if (timedOut) {
    c.status = "stopped after " + std::to_string(int(o.cellLimitS)) + " s";
    return c;
  }
  try {
    FromJson(ParseJson(text, "the benchmark cell's result"), c);
  } catch (const std::exception&) {
    c.status = WIFSIGNALED(status) ? "crashed (signal " + std::to_string(WTERMSIG(status)) + ")"
                                   : "failed: no result";
  }
  return c;
}

std::vector<std::string> SplitCommaList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty())
      out.push_back(item);
  return out;
}

std::string BenchCsv(const std::vector<BenchCell>& cells) {
  std::ostringstream os;
  os << std::setprecision(6);
  os << "method,backend,shell,voxmap,status,engine,elements,frames,median_ms,p99_ms,mean_ms,sd_ms,"
        "max_ms,thrust_N,torque_Nmm,ref_thrust_N,ref_torque_Nmm,thrust_error,torque_error,"
        "force_error,engaged_cutting,peak_memory_MiB,setup_s,coefficients,calibrated\n";
  for (const auto& c : cells) {
    std::string status = c.status;
    std::replace(status.begin(), status.end(), ',', ';');
    std::replace(status.begin(), status.end(), '\n', ' ');
    os << ToString(c.method) << ',' << c.backend << ',' << c.shell << ',' << c.voxmap << ','
       << status << ',' << c.engine << ',' << c.elements << ',' << c.frames << ',' << c.medianMs
       << ',' << c.p99Ms << ',' << c.meanMs << ',' << c.sdMs << ',' << c.maxMs << ',' << c.thrustN
       << ',' << c.torqueNmm << ',' << c.refThrustN << ',' << c.refTorqueNmm << ',' << c.thrustError
       << ',' << c.torqueError << ',' << c.forceError << ',' << c.engagedCutting << ','
       << c.peakMemoryMb << ',' << c.setupS << ',' << c.coefficients << ','
       << (c.calibrated ? "true" : "false") << '\n';
  }
  return os.str();
}

std::vector<BenchCell> ParseBenchCsv(const std::string& text, const std::string& source) {
  auto split = [&](const std::string& line) { return SplitCsvRecord(line, source); };
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line.empty())
    throw std::runtime_error("the benchmark table '" + source + "' is empty");
  const std::vector<std::string> header = split(line);
  std::map<std::string, size_t> column;
  for (size_t i = 0; i < header.size(); ++i)
    column[header[i]] = i;
  for (const char* name :
       {"method", "backend", "shell", "voxmap", "status", "median_ms", "p99_ms", "force_error"})
    if (!column.count(name))
      throw std::runtime_error("the benchmark table '" + source + "' has no column '" + name + "'");
  std::vector<BenchCell> cells;
  int lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty())
      continue;
    const std::vector<std::string> f = split(line);
    const std::string at = source + ":" + std::to_string(lineNo) + ": ";
    if (f.size() < header.size())
      throw std::runtime_error(at + std::to_string(f.size()) + " fields, the header has " +
                               std::to_string(header.size()));
    auto number = [&](const char* name, auto& out) {
      const auto it = column.find(name);
      if (it == column.end())
        return;
      const std::string& t = f[it->second];
      double v = 0;
      const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
      if (ec != std::errc() || ptr != t.data() + t.size() || !std::isfinite(v))
        throw std::runtime_error(at + "column '" + name + "' is not a number: '" + t + "'");
      out = static_cast<std::remove_reference_t<decltype(out)>>(v);
    };
    BenchCell c;
    try {
      c.method = MethodFromString(f[column["method"]]);
    } catch (const std::exception& e) {
      throw std::runtime_error(at + "column 'method': " + e.what());
    }
    c.backend = f[column["backend"]];
    c.status = f[column["status"]];
    if (column.count("engine"))
      c.engine = f[column["engine"]];
    // Resolutions: whole numbers of cells in [8, 4096], as the bench accepts them.
    auto resolution = [&](const char* name, int& out) {
      double v = 0;
      number(name, v);
      if (v != std::floor(v) || v < 8 || v > 4096)
        throw std::runtime_error(at + "column '" + name + "' is not a resolution in 8..4096: '" +
                                 f[column[name]] + "'");
      out = int(v);
    };
    resolution("shell", c.shell);
    resolution("voxmap", c.voxmap);
    number("elements", c.elements);
    number("frames", c.frames);
    number("median_ms", c.medianMs);
    number("p99_ms", c.p99Ms);
    number("mean_ms", c.meanMs);
    number("sd_ms", c.sdMs);
    number("max_ms", c.maxMs);
    number("thrust_N", c.thrustN);
    number("torque_Nmm", c.torqueNmm);
    number("ref_thrust_N", c.refThrustN);
    number("ref_torque_Nmm", c.refTorqueNmm);
    number("thrust_error", c.thrustError);
    number("torque_error", c.torqueError);
    number("force_error", c.forceError);
    number("engaged_cutting", c.engagedCutting);
    number("peak_memory_MiB", c.peakMemoryMb);
    number("setup_s", c.setupS);
    if (column.count("coefficients"))
      c.coefficients = f[column["coefficients"]];
    if (column.count("calibrated")) {
      const std::string& t = f[column["calibrated"]];
      if (t != "true" && t != "false")
        throw std::runtime_error(at + "column 'calibrated' is not true or false: '" + t + "'");
      c.calibrated = t == "true";
    }
    cells.push_back(c);
  }
  return cells;
}

std::string BenchTable(const std::vector<BenchCell>& cells, Method method, const std::string& title,
                       const std::vector<int>& shells, const std::vector<int>& voxmaps) {
  std::ostringstream os;
  os << std::fixed;
  os << "# " << title << "\n";
  // The coefficient sets the cells' forces come from (ForceModel::Provenance).
  std::vector<std::string> sets;
  for (const auto& c : cells)
    if (c.method == method && c.status == "ok" && !c.coefficients.empty()) {
      const std::string set =
          c.coefficients + (c.calibrated ? " (calibrated)" : " (not calibrated)");
      if (std::find(sets.begin(), sets.end(), set) == sets.end())
        sets.push_back(set);
    }
  if (!sets.empty()) {
    os << "\nCoefficients: ";
    for (size_t i = 0; i < sets.size(); ++i)
      os << (i ? ", " : "") << sets[i];
    os << "\n";
  }
  std::vector<std::string> backends;
  for (const auto& c : cells)
    if (c.method == method &&
        std::find(backends.begin(), backends.end(), c.backend) == backends.end())
      backends.push_back(c.backend);
  std::sort(backends.begin(), backends.end()); // cpu, then opencl
  auto find = [&](const std::string& be, int s, int v) -> const BenchCell* {
    for (const auto& c : cells)
      if (c.method == method && c.backend == be && c.shell == s && c.voxmap == v)
        return &c;
    return nullptr;
  };
  for (const auto& be : backends) {
    for (int table = 0; table < 3; ++table) {
      static const char* what[] = {"median (sd) of the frame time, ms", "p99 of the frame time, ms",
                                   "force error (max of thrust and torque relative error)"};
      os << "\n## " << be << " backend: " << what[table] << "\n\n| Point shell resolution |";
      for (int v : voxmaps)
        os << ' ' << v << "^3 |";
      os << "\n|---|";
      for (size_t i = 0; i < voxmaps.size(); ++i)
        os << "---|";
      os << '\n';
      for (int s : shells) {
        os << "| " << s << "^3 |";
        for (int v : voxmaps) {
          const BenchCell* c = find(be, s, v);
          if (!c)
            os << " |";
          else if (c->status != "ok")
            os << " " << c->status << " |";
          else if (table == 0)
            os << std::setprecision(3) << ' ' << c->medianMs << " (" << c->sdMs << ") |";
          else if (table == 1)
            os << std::setprecision(3) << ' ' << c->p99Ms << " |";
          else
            os << std::setprecision(2) << ' ' << 100 * c->forceError << " % |";
        }
        os << '\n';
      }
    }
  }
  return os.str();
}

} // namespace bm
