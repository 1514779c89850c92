// Every planner the registry builds: complete entries, actions inside the box, one seed one
// action, and settings errors that name the key. Tests of one planner live beside its file.
#include "cmbrl/planning/planner_registry.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <string>

#include "tests/error_message.h"
#include "tests/planning/analytic_objectives.h"

namespace cmbrl {
namespace {

using testing::CorridorObjective;
using testing::ErrorMessage;
using testing::QuadraticObjective;
using testing::RepeatedTarget;

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
    EXPECT_GT(work.total(), 0);
    EXPECT_GE(work.iterations(), 1);
    EXPECT_GE(work.largest(), work.samples.back());
    QuadraticObjective objective(RepeatedTarget(0.1f, 0.1f));
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

TEST(PlannerTest, BoundsAlwaysHold) {
  for (const std::string& name : PlannerNames()) {
    QuadraticObjective objective(RepeatedTarget(3.0f, -2.0f));  // the optimum lies outside the box
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

// Wants the first action's x as high as possible, and violates wherever it is positive: the one
// penalty of PlannerSettings decides which side CEM and random shooting choose.
class PositiveXViolates : public Objective {
 public:
  ObjectiveValues Evaluate(const torch::Tensor& actions) override {
    const torch::Tensor x = actions.select(1, 0).select(1, 0);  // (N)
    return {-x, (x > 0).to(torch::kFloat)};
  }
};

TEST(PlannerFactoryTest, CemAndRandomScoreWithTheSettingsPenalty) {
  for (const std::string name : {"cem", "random"}) {
    SCOPED_TRACE(name);
    PlannerSettings settings;
    settings.penalty = 0.0;  // the reward alone: as far right as the box allows
    PositiveXViolates objective;
    EXPECT_GT(MakePlanner(name, settings, 2)->Plan(objective).action[0].item<float>(), 0.5f);
    settings.penalty = 100.0;  // a violation costs more than any reward: stay left of 0
    EXPECT_LE(MakePlanner(name, settings, 2)->Plan(objective).action[0].item<float>(), 0.0f);
  }
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
            "unknown planner 'mppi': expected one of rce, cem, random, rce-icem");
  for (const std::string name : {"rce", "cem", "random"}) {
    settings = PlannerSettings{};
    settings.penalty = -1.0;
    EXPECT_EQ(ErrorMessage([&] { MakePlanner(name, settings, 0); }),
              "penalty is -1: expected a number in [0, 1e9]")
        << name;
  }
  settings = PlannerSettings{};
  settings.random.samples = 0;
  EXPECT_EQ(ErrorMessage([&] { MakePlanner("random", settings, 0); }),
            "random_samples is 0: expected 1 to 10000000");
}

}  // namespace
}  // namespace cmbrl
