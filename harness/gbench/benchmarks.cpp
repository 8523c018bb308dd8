// nurbsbench_gbench: every available strategy x a few scenes x grid sizes as Google Benchmark
// cases, so the usual --benchmark_filter / --benchmark_format=json / compare.py work. Each case
// times evaluate() alone (prepare outside the loop) and reports points/s and max_ulp against the
// reference.
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <random>

#include "harness/metrics.h"
#include "harness/runner.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace {

using namespace nurbs;

void evaluate_benchmark(benchmark::State& state, const StrategyEntry* entry, const Scene* scene,
                        Sampling sampling, Precision precision) {
  const EvalRequest request{sampling, precision, false};
  if (auto refused = refusal_reason(entry->capabilities(), *scene, request)) {
    state.SkipWithError(("refused: " + *refused).c_str());
    return;
  }
  std::unique_ptr<Strategy> strategy;
  try {
    strategy = entry->create(StrategyOptions{});
    strategy->prepare(*scene, request);
    strategy->evaluate();  // warm-up
  } catch (const std::exception& e) {
    state.SkipWithError((std::string("failed: ") + e.what()).c_str());
    return;
  }
  for (auto _ : state) strategy->evaluate();
  const std::size_t points = total_samples(sample_parameters(*scene, sampling));
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(points),
                                                  benchmark::Counter::kIsIterationInvariantRate);
  const Accuracy accuracy =
      measure_accuracy(*scene, strategy->read_back(),
                       evaluate_reference(*scene, sample_parameters(*scene, sampling), false));
  state.counters["max_ulp"] = accuracy.max_ulp;
  state.SetLabel(strategy->device().name);
}

// The memory-write ceiling a grid evaluator's output stream runs into: every thread storing
// floats into its own share of a buffer the size of a 1024x1024 float32 xyz result (12 MiB, well
// past the caches). Reported as bytes/s; the cpu-tensor f32 goal is a fraction of it.
void store_bandwidth(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0)) * state.range(0) * 3;
  std::vector<float> buffer(n);
  float value = 1.0f;
  for (auto _ : state) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) buffer[i] = value;
    benchmark::DoNotOptimize(buffer.data());
    benchmark::ClobberMemory();
    value += 1.0f;
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * n * sizeof(float));
  state.SetLabel(fmt::format("{} threads", omp_get_max_threads()));
}

// A random rational bicubic 12x12 patch: random non-uniform interior knots, points in [-10, 10]^3,
// weights in [0.5, 2] (fixed seed, so every run times the same surface).
Scene random_bicubic_12x12() {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> unit(0.0, 1.0), coordinate(-10.0, 10.0), weight(0.5, 2.0);
  Surface s;
  s.name = "random";
  s.degree_u = s.degree_v = 3;
  s.count_u = s.count_v = 12;
  for (std::vector<double>* knots : {&s.knots_u, &s.knots_v}) {
    std::vector<double> interior(8);
    for (double& k : interior) k = unit(rng);
    std::sort(interior.begin(), interior.end());
    knots->assign(4, 0.0);
    knots->insert(knots->end(), interior.begin(), interior.end());
    knots->insert(knots->end(), 4, 1.0);
  }
  for (int k = 0; k < 144; ++k) {
    s.points.push_back({coordinate(rng), coordinate(rng), coordinate(rng)});
    s.weights.push_back(weight(rng));
  }
  return Scene{"random-bicubic-12x12", "random rational bicubic 12x12 patch", {s}};
}

}  // namespace

int main(int argc, char** argv) {
  static std::vector<Scene> scenes;
  for (const char* name : {"patch144", "tan64", "sphere", "degree-5"})
    scenes.push_back(*make_builtin_scene(name));
  scenes.push_back(random_bicubic_12x12());
  benchmark::RegisterBenchmark("limit-store-bandwidth/1024x1024/f32", store_bandwidth)
      ->Arg(1024)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  for (const StrategyEntry& entry : strategy_registry()) {
    if (!entry.probe().available) continue;
    for (const Scene& scene : scenes)
      for (int n : {64, 256, 1024})
        for (Precision precision : {Precision::f32, Precision::f64}) {
          if (!entry.capabilities().supports(precision)) continue;
          Sampling sampling;
          sampling.grid_u = sampling.grid_v = n;
          benchmark::RegisterBenchmark(
              fmt::format("{}/{}/{}x{}/{}", entry.name, scene.name, n, n, to_string(precision))
                  .c_str(),
              evaluate_benchmark, &entry, &scene, sampling, precision)
              ->Unit(benchmark::kMillisecond)
              ->UseRealTime();
        }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
