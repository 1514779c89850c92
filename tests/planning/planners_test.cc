#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>

#include "cmbrl/core/torch_util.h"
#include "cmbrl/planning/planner_registry.h"
#include "cmbrl/planning/truncated_normal.h"
#include "tests/error_message.h"
#include "tests/planning/analytic_objectives.h"

namespace cmbrl {
namespace {

using testing::CorridorObjective;
using testing::ErrorMessage;
using testing::QuadraticObjective;

// Targets for (H = 8, A = 2): every step wants (0.5, -0.3).
std::vector<float> Target(float x, float y) {
  std::vector<float> target;
  for (int t = 0; t < 8; ++t) {
    target.push_back(x);
    target.push_back(y);
  }
  return std::vector<float>(target);
}

torch::Tensor TargetTensor(float x, float y) { return torch::tensor(Target(x, y)).view({8, 2}); }

TEST(PlannerRegistryTest, EveryEntryIsCompleteAndOneIsThePapersMethod) {
  int papers = 0;
  PlannerSettings settings;
  settings.penalty = 123.0;
  for (const PlannerEntry& entry : Planners()) {
    SCOPED_TRACE(entry.name);
    EXPECT_FALSE(entry.label.empty());
    EXPECT_EQ(&FindPlanner(entry.name), &entry);
    EXPECT_EQ(PlannerLabel(entry.name), entry.label);
    papers += entry.is_papers_method;
    const PlanWork work = entry.work(settings);
    EXPECT_GT(work.samples, 0);
    EXPECT_GE(work.iterations, 1);
    QuadraticObjective objective(Target(0.1f, 0.1f));
    EXPECT_EQ(entry.make(settings, 1)->Plan(objective).action.numel(), 2);
  }
  EXPECT_EQ(papers, 1);
  // The registry builds every planner that planning_options.h names, in its order, and no other.
  ASSERT_EQ(Planners().size(), PlannerInfos().size());
  for (size_t i = 0; i < Planners().size(); ++i) {
    EXPECT_EQ(Planners()[i].name, PlannerInfos()[i].name);
    EXPECT_EQ(&FindPlannerInfo(Planners()[i].name), &PlannerInfos()[i]);
  }
  EXPECT_EQ(FindPlanner("rce").propagation, Propagation::kPerMember);
  EXPECT_EQ(FindPlanner("cem").propagation, Propagation::kEnsembleMean);
  EXPECT_EQ(PlannerLabel("mppi"), "mppi");  // a planner of another build keeps its name
  EXPECT_EQ(FindPlannerOrNull("mppi"), nullptr);
}

TEST(CrossEntropyTest, CemAndRceFindAQuadraticOptimum) {
  for (const std::string name : {"cem", "rce"}) {
    QuadraticObjective objective(Target(0.5f, -0.3f));
    std::unique_ptr<Planner> planner = MakePlanner(name, PlannerSettings{}, 1);
    const PlanResult plan = planner->Plan(objective);
    // The paper's budget (500 samples, 12 elites, 8 iterations) on 16 dimensions: the final
    // mean lands within 0.1 of the optimum in every coordinate (measured: about 0.03).
    EXPECT_LT((plan.sequence - TargetTensor(0.5f, -0.3f)).abs().max().item<float>(), 0.1f) << name;
    EXPECT_EQ(plan.action.sizes(), torch::IntArrayRef({2}));
    // Every variance fell to epsilon (0.01) within the 8 iterations (measured: after 6).
    EXPECT_GE(plan.diagnostics.iterations.item<std::int64_t>(), 2);
    EXPECT_LE(plan.diagnostics.iterations.item<std::int64_t>(), 8);
    EXPECT_EQ(plan.diagnostics.feasible_fraction.item<float>(), 1.0f);
    EXPECT_EQ(plan.diagnostics.infeasible_elite_fraction.item<float>(), 0.0f);
  }
}

TEST(CrossEntropyTest, MoreIterationsGetCloser) {
  PlannerSettings settings;
  settings.cross_entropy.max_iterations = 30;
  settings.cross_entropy.epsilon = 0.0;
  QuadraticObjective objective(Target(0.5f, -0.3f));
  const PlanResult plan = MakePlanner("rce", settings, 2)->Plan(objective);
  EXPECT_LT((plan.sequence - TargetTensor(0.5f, -0.3f)).abs().max().item<float>(), 0.02f);
  EXPECT_EQ(plan.diagnostics.iterations.item<std::int64_t>(), 30);
}

TEST(CrossEntropyTest, StopsOnceTheVarianceIsSmall) {
  PlannerSettings settings;
  settings.cross_entropy.epsilon = 10.0;  // the first update already brings the variance below
  QuadraticObjective objective(Target(0.5f, -0.3f));
  const PlanResult plan = MakePlanner("cem", settings, 2)->Plan(objective);
  EXPECT_EQ(plan.diagnostics.iterations.item<std::int64_t>(), 1);
}

TEST(RandomShootingTest, FindsAnOptimumInFewDimensions) {
  PlannerSettings settings;
  settings.problem.horizon = 1;
  QuadraticObjective objective({0.5f, -0.3f});
  const PlanResult plan = MakePlanner("random", settings, 3)->Plan(objective);
  // 5000 uniform samples of [-1, 1]^2: the nearest lies within about 0.02 of any point.
  EXPECT_LT((plan.action - torch::tensor({0.5f, -0.3f})).abs().max().item<float>(), 0.05f);
  EXPECT_EQ(plan.diagnostics.infeasible_elite_fraction.item<float>(), 0.0f);
}

TEST(PlannerTest, BoundsAlwaysHold) {
  for (const std::string& name : PlannerNames()) {
    QuadraticObjective objective(Target(3.0f, -2.0f));  // the optimum lies outside the box
    const PlanResult plan = MakePlanner(name, PlannerSettings{}, 4)->Plan(objective);
    EXPECT_GE(objective.lowest(), -1.0f) << name;
    EXPECT_LE(objective.highest(), 1.0f) << name;
    EXPECT_LE(plan.sequence.abs().max().item<float>(), 1.0f) << name;
    // Pushed toward the corner nearest the optimum. The smoothed mean of truncated samples
    // approaches a bound only gradually (measured: about 0.54 after CEM's 6 iterations).
    EXPECT_GT(plan.action[0].item<float>(), 0.3f) << name;
    EXPECT_LT(plan.action[1].item<float>(), -0.3f) << name;
  }
}

TEST(PlannerTest, SameSeedSameActionOtherSeedOtherAction) {
  for (const std::string& name : PlannerNames()) {
    CorridorObjective objective(0.1);
    const torch::Tensor a = MakePlanner(name, PlannerSettings{}, 5)->Plan(objective).action;
    const torch::Tensor b = MakePlanner(name, PlannerSettings{}, 5)->Plan(objective).action;
    const torch::Tensor c = MakePlanner(name, PlannerSettings{}, 6)->Plan(objective).action;
    EXPECT_TRUE(torch::equal(a, b)) << name;
    EXPECT_FALSE(torch::equal(a, c)) << name;
  }
}

TEST(PlannerTest, GeneratorStateRoundTrips) {
  std::unique_ptr<Planner> planner = MakePlanner("rce", PlannerSettings{}, 7);
  CorridorObjective objective(0.1);
  const torch::Tensor state = planner->GeneratorState();
  const torch::Tensor first = planner->Plan(objective).action;
  planner->SetGeneratorState(state);
  EXPECT_TRUE(torch::equal(planner->Plan(objective).action, first));
}

// Paper Section V-D: near the constraint only a few samples are feasible. RCE keeps its elites
// to those; the penalty CEM fills its twelve with infeasible samples. Corridor half-width 0.1:
// measured over 20 seeds, RCE's elites were 7% infeasible and CEM's 25%.
TEST(RobustCrossEntropyTest, ReturnsFeasiblePlansAndDrawsFewerInfeasibleElitesThanCem) {
  double rce_infeasible = 0.0, cem_infeasible = 0.0;
  constexpr int kSeeds = 10;
  for (int seed = 0; seed < kSeeds; ++seed) {
    CorridorObjective objective(0.1);
    const PlanResult rce = MakePlanner("rce", PlannerSettings{}, seed)->Plan(objective);
    const PlanResult cem = MakePlanner("cem", PlannerSettings{}, seed)->Plan(objective);
    EXPECT_EQ(objective.ConstraintOf(rce.sequence), 0.0f) << "seed " << seed;
    rce_infeasible += rce.diagnostics.infeasible_elite_fraction.item<float>();
    cem_infeasible += cem.diagnostics.infeasible_elite_fraction.item<float>();
    // The plan heads for the goal along the corridor.
    EXPECT_GT(rce.action[0].item<float>(), 0.3f);
  }
  EXPECT_LT(rce_infeasible, 0.5 * cem_infeasible);
}

TEST(EliteWeightsTest, RobustRuleKeepsOnlyFeasibleSamplesWhenEnough) {
  CrossEntropyOptions options;
  options.population = 20;
  CrossEntropyPlanner rce(PlanningProblem{}, options, EliteRule::kRobust, 0);
  CrossEntropyPlanner cem(PlanningProblem{}, options, EliteRule::kPenalty, 0);
  // Samples 0..6 feasible with reward cost 10 + i; 7..19 infeasible but rewarding (cost i).
  torch::Tensor reward = torch::arange(20, torch::kFloat);
  reward.slice(0, 0, 7) += 10;
  torch::Tensor constraint = torch::ones({20});
  constraint.slice(0, 0, 7).zero_();
  constraint.slice(0, 7, 12).fill_(0.001f);  // barely violating: the penalty still ranks them
  const torch::Tensor robust = rce.EliteWeights({reward, constraint});
  EXPECT_TRUE(torch::equal(robust, (torch::arange(20) < 7).to(torch::kFloat)));
  const torch::Tensor penalty = cem.EliteWeights({reward, constraint});
  EXPECT_EQ(penalty.sum().item<float>(), 12.0f);
  EXPECT_EQ(penalty.slice(0, 0, 12).sum().item<float>(), 12.0f);  // 7 feasible + 5 barely
}

TEST(EliteWeightsTest, RobustRulePadsWithTheLeastViolatingWhenTooFew) {
  CrossEntropyOptions options;
  options.population = 10;
  options.elites = 5;
  CrossEntropyPlanner rce(PlanningProblem{}, options, EliteRule::kRobust, 0);
  // Two feasible samples (3 and 8); constraint costs rise with the index otherwise.
  const torch::Tensor reward = torch::zeros({10});
  torch::Tensor constraint = torch::arange(1, 11, torch::kFloat);
  constraint[3] = 0;
  constraint[8] = 0;
  const torch::Tensor weights = rce.EliteWeights({reward, constraint});
  // Feasible 3 and 8, plus the first 5 - 2 = 3 by constraint cost: 3 and 8 again (they sort
  // first, so they count twice), then sample 0.
  const torch::Tensor expected = torch::tensor({1.f, 0.f, 0.f, 2.f, 0.f, 0.f, 0.f, 0.f, 2.f, 0.f});
  EXPECT_TRUE(torch::equal(weights, expected)) << weights;
}

TEST(PlannerTest, WarmStartStartsFromThePreviousPlanShifted) {
  // With alpha 0.99 one iteration barely moves the mean, so the plan shows where it started.
  PlannerSettings settings;
  settings.cross_entropy.max_iterations = 1;
  settings.cross_entropy.alpha = 0.99;
  QuadraticObjective objective(Target(0.5f, -0.3f));
  settings.cross_entropy.warm_start = true;
  std::unique_ptr<Planner> warm = MakePlanner("cem", settings, 9);
  const torch::Tensor first = warm->Plan(objective).sequence;
  const torch::Tensor second = warm->Plan(objective).sequence;
  // second = 0.99 * (first shifted one step, zero appended) + 0.01 * elite mean (|.| <= 1).
  EXPECT_TRUE(torch::allclose(second.slice(0, 0, 7), 0.99 * first.slice(0, 1), 0, 0.011));
  EXPECT_LE(second[7].abs().max().item<float>(), 0.011f);
  // Reset forgets it: the next plan starts from zero again.
  warm->Reset();
  EXPECT_LE(warm->Plan(objective).sequence.abs().max().item<float>(), 0.011f);
  // Without warm start every plan starts from zero.
  settings.cross_entropy.warm_start = false;
  std::unique_ptr<Planner> cold = MakePlanner("cem", settings, 9);
  cold->Plan(objective);
  EXPECT_LE(cold->Plan(objective).sequence.abs().max().item<float>(), 0.011f);
}

TEST(TruncatedNormalTest, StaysInTheBoxAndMatchesTheTruncatedMoments) {
  at::Generator generator = MakeCpuGenerator(0);
  const torch::Tensor mean = torch::tensor({0.0f, 0.8f, -0.5f});
  const torch::Tensor variance = torch::tensor({1.0f, 1.0f, 1e-4f});
  const torch::Tensor x = SampleTruncatedNormal(mean, variance, 200000, -1, 1, generator);
  EXPECT_GE(x.min().item<float>(), -1.0f);
  EXPECT_LE(x.max().item<float>(), 1.0f);
  const torch::Tensor m = x.mean(0);
  // N(0, 1) on [-1, 1]: mean 0, variance 1 - 2 phi(1) / (2 Phi(1) - 1) = 0.2911.
  EXPECT_NEAR(m[0].item<float>(), 0.0f, 0.005f);
  EXPECT_NEAR(x.select(1, 0).var().item<float>(), 0.2911f, 0.005f);
  // N(0.8, 1) on [-1, 1]: mean 0.8 + (phi(-1.8) - phi(0.2)) / (Phi(0.2) - Phi(-1.8)) = 0.2256.
  EXPECT_NEAR(m[1].item<float>(), 0.2256f, 0.005f);
  // A narrow normal well inside the box is untouched by the bounds.
  EXPECT_NEAR(m[2].item<float>(), -0.5f, 1e-3f);
  EXPECT_NEAR(x.select(1, 2).std().item<float>(), 0.01f, 1e-3f);
}

TEST(PlannerFactoryTest, BadSettingsAreNamed) {
  PlannerSettings settings;
  settings.cross_entropy.elites = 600;
  EXPECT_EQ(ErrorMessage([&] { MakePlanner("rce", settings, 0); }),
            "elites is 600: expected between 1 and population (500)");
  settings = PlannerSettings{};
  settings.problem.horizon = 0;
  EXPECT_EQ(ErrorMessage([&] { MakePlanner("cem", settings, 0); }),
            "horizon is 0: expected 1 to 1000 steps");
  EXPECT_EQ(ErrorMessage([&] { MakePlanner("mppi", PlannerSettings{}, 0); }),
            "unknown planner 'mppi': expected one of rce, cem, random");
  settings = PlannerSettings{};
  settings.random.samples = 0;
  EXPECT_EQ(ErrorMessage([&] { MakePlanner("random", settings, 0); }),
            "samples is 0: expected 1 to 10000000");
}

}  // namespace
}  // namespace cmbrl
