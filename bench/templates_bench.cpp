// One-off costs of particle templates: union integration and the pseudo-ellipsoid fit.
// These run once per particle type per simulation; the numbers show that they stay far
// below a second even at high resolution.
#include <benchmark/benchmark.h>

#include "bushel/particles/pseudo_ellipsoid.hpp"
#include "bushel/particles/template_library.hpp"
#include "bushel/particles/union_moments.hpp"

namespace {

void integrate(benchmark::State& state, const char* name) {
  const auto& spheres = bushel::TemplateLibrary::builtin().get(name).spheres;
  const int resolution = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(bushel::integrate_union(spheres, resolution));
  state.counters["spheres"] = static_cast<double>(spheres.size());
}

void BM_IntegrateLarge5s(benchmark::State& state) { integrate(state, "large_5s"); }
void BM_IntegrateLargeAsg(benchmark::State& state) { integrate(state, "large_asg"); }
BENCHMARK(BM_IntegrateLarge5s)->Arg(100)->Arg(400)->Arg(1600)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IntegrateLargeAsg)->Arg(100)->Arg(400)->Arg(1600)->Unit(benchmark::kMillisecond);

void BM_PseudoEllipsoidFit(benchmark::State& state) {
  bushel::PseudoEllipsoidSpec spec;
  spec.length = 6.12e-3;
  spec.width = 3.05e-3;
  spec.spheres = static_cast<int>(state.range(0));
  spec.mass = 0.0346e-3;
  for (auto _ : state) benchmark::DoNotOptimize(bushel::make_pseudo_ellipsoid(spec, "bench"));
}
BENCHMARK(BM_PseudoEllipsoidFit)->Arg(5)->Arg(7)->Unit(benchmark::kMillisecond);

}  // namespace
