// Google Benchmark: agent steps of each Goal task under a random policy.
#include <benchmark/benchmark.h>

#include "cmbrl/agent/policy.h"
#include "cmbrl/env/registry.h"

namespace cmbrl {
namespace {

void BM_EnvStep(benchmark::State& state, const std::string& task, Variant variant) {
  std::unique_ptr<Env> env = MakeEnv(task, variant);
  RandomPolicy policy(env->action_spec(), 1);
  std::vector<double> observation = env->Reset(0);
  for (auto _ : state) {
    StepResult step = env->Step(policy.Act(observation));
    observation = step.truncated || step.terminated ? env->Reset() : std::move(step.observation);
    benchmark::DoNotOptimize(observation.data());
  }
  state.counters["agent_steps_per_second"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void RegisterAll() {
  for (const TaskEntry& entry : Tasks()) {
    const std::string& task = entry.name;
    for (const Variant variant : {Variant::kPaper, Variant::kStandard}) {
      if (IsPaperWorld(variant) && !HasPaperVariant(entry)) continue;
      benchmark::RegisterBenchmark(("EnvStep/" + task + "/" + VariantName(variant)).c_str(),
                                   BM_EnvStep, task, variant);
    }
  }
}

}  // namespace
}  // namespace cmbrl

int main(int argc, char** argv) {
  cmbrl::RegisterAll();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
