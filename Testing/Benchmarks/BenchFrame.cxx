// Google Benchmark micro-benchmarks of one haptic frame (the engine alone, no trial bookkeeping):
// the drilling scene brought to full engagement, then frames timed one by one. A benchmark, not a
// test: it prints figures (run build/Testing/Benchmarks/BMBenchFrame); `bmsim bench` sweeps the
// whole resolution grid.
#include <benchmark/benchmark.h>

#include <memory>

#include "bmEdgeQuadrature.h"
#include "bmMachiningSetup.h"

namespace {

// A drilling setup fed to full engagement; frames continue the feed from there.
struct EngagedDrill {
  EngagedDrill(bm::Method method, int shell, int voxmap, int threads) {
    bm::Scene s;
    s.method = method;
    s.shellResolution = shell;
    s.voxmapResolution = voxmap;
    s.threads = threads;
    setup = std::make_unique<bm::MachiningSetup>(s, bm::MakeSceneBlock(s));
    step = s.trial.feedMmPerRev * s.trial.speedRpm / 60.0 * s.trial.frameS;
    const double full = bm::FullEngagementDepth(setup->Tool()) + 2 * setup->Bone().Spacing();
    for (depth = -0.005; depth < full; depth += step)
      Frame();
  }
  bm::FrameResult Frame() {
    bm::FrameInput in;
    in.position = Eigen::Vector3d(0, 0, -depth);
    in.motion = Eigen::Vector3d(0, 0, -step);
    depth += step;
    return setup->GetEngine().Step(in);
  }
  std::unique_ptr<bm::MachiningSetup> setup;
  double step = 0, depth = 0;
};

void Frame(benchmark::State& state, bm::Method method) {
  EngagedDrill d(method, int(state.range(0)), int(state.range(1)), int(state.range(2)));
  int64_t elements = 0;
  for (auto _ : state) {
    const bm::FrameResult r = d.Frame();
    elements = r.visitedElements;
    benchmark::DoNotOptimize(r.thrustFixed);
  }
  state.counters["visited_elements"] = double(elements);
}

void LazarFrame(benchmark::State& state) {
  Frame(state, bm::Method::Lazar);
}
void ZhengFrame(benchmark::State& state) {
  Frame(state, bm::Method::Zheng);
}

// Args: shell resolution, voxmap resolution, threads.
BENCHMARK(LazarFrame)
    ->Args({512, 256, 1})
    ->Args({1024, 256, 1})
    ->Args({1024, 256, 2})
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(ZhengFrame)
    ->Args({512, 256, 1})
    ->Args({512, 256, 2})
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

} // namespace

BENCHMARK_MAIN();
