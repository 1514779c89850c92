#include "cmbrl/models/step_model.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cmbrl/core/check.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

// Steps of a 1-D walk, inputs (state, action, next state), rewarded by minus the next state's
// distance to 1: what a learned reward learns from a run's transitions.
struct Steps {
  torch::Tensor inputs, targets;  // rewards, or terminations
};

Steps WalkSteps(int n, std::uint64_t seed) {
  at::Generator generator = at::detail::createCPUGenerator(seed);
  const torch::Tensor state = torch::rand({n, 1}, generator) * 4 - 2;
  const torch::Tensor action = torch::rand({n, 1}, generator) * 2 - 1;
  const torch::Tensor next = state + 0.1 * action;
  return {torch::cat({state, action, next}, 1), -(next.squeeze(1) - 1).abs()};
}

StepModelOptions Small() {
  StepModelOptions options;
  options.hidden_sizes = {32, 32};
  options.max_epochs = 60;
  return options;
}

TEST(StepModelTest, LearnsARewardWellBelowItsSpreadOnHeldOutSteps) {
  StepModel model(StepSignal::kReward, 3, Small(), 1);
  const Steps train = WalkSteps(3000, 1), test = WalkSteps(500, 2);
  const StepFitReport report = model.Fit(train.inputs, train.targets);
  EXPECT_GT(report.epochs, 0);
  EXPECT_EQ(report.train_size + report.validation_size, 3000);
  const double variance = test.targets.var(0, false).item<double>();
  const double mse = (model.Predict(test.inputs) - test.targets).pow(2).mean().item<double>();
  EXPECT_LT(mse, 0.05 * variance) << "held-out MSE " << mse << ", variance " << variance;
  EXPECT_LT(report.validation_loss, 0.05 * variance);
  // Any leading shape: (2, 5, 3) inputs give (2, 5) rewards.
  EXPECT_EQ(model.Predict(test.inputs.slice(0, 0, 10).view({2, 5, 3})).sizes(),
            (std::vector<std::int64_t>{2, 5}));
}

TEST(StepModelTest, TheSameSeedFitsTheSameModelAndAFileCarriesIt) {
  const Steps steps = WalkSteps(400, 3);
  StepModel a(StepSignal::kReward, 3, Small(), 7), b(StepSignal::kReward, 3, Small(), 7),
      other(StepSignal::kReward, 3, Small(), 8);
  EXPECT_TRUE(a.Predict(steps.inputs).eq(0).all().item<bool>());  // no fit yet: zeros
  a.Fit(steps.inputs, steps.targets);
  b.Fit(steps.inputs, steps.targets);
  other.Fit(steps.inputs, steps.targets);
  EXPECT_TRUE(a.Predict(steps.inputs).equal(b.Predict(steps.inputs)));
  EXPECT_FALSE(a.Predict(steps.inputs).equal(other.Predict(steps.inputs)));

  // Saved and loaded, it predicts the same, and its next fit is the one `a` makes (the
  // generator travels with it).
  const std::string path = (testing::TestTempDir() / "reward_model.pt").string();
  a.Save(path);
  StepModel loaded(StepSignal::kReward, 3, Small(), 99);
  loaded.Load(path);
  EXPECT_TRUE(loaded.Predict(steps.inputs).equal(a.Predict(steps.inputs)));
  a.Fit(steps.inputs, steps.targets);
  loaded.Fit(steps.inputs, steps.targets);
  EXPECT_TRUE(loaded.Predict(steps.inputs).equal(a.Predict(steps.inputs)));

  StepModelOptions wider = Small();
  wider.hidden_sizes = {64, 32};
  StepModel mismatched(StepSignal::kReward, 3, wider, 1);
  EXPECT_THAT(ErrorMessage([&] { mismatched.Load(path); }),
              ::testing::HasSubstr("this model's is [3, 64] (other hidden_sizes)"));
  EXPECT_THAT(ErrorMessage([&] { StepModel(StepSignal::kReward, 4, Small(), 1).Load(path); }),
              ::testing::HasSubstr("holds a reward model of 3 inputs"));
  EXPECT_THAT(ErrorMessage([&] { StepModel(StepSignal::kTermination, 3, Small(), 1).Load(path); }),
              ::testing::HasSubstr("holds a reward model, not a termination model"));
}

TEST(StepModelTest, BadInputsAndOptionsAreNamed) {
  StepModel model(StepSignal::kReward, 3, Small(), 1);
  EXPECT_THAT(ErrorMessage([&] {
                model.Fit(torch::zeros({1, 3}), torch::zeros({1}));
              }),
              ::testing::HasSubstr("needs at least 2 steps"));
  EXPECT_THAT(ErrorMessage([&] {
                model.Fit(torch::zeros({5, 2}), torch::zeros({5}));
              }),
              ::testing::HasSubstr("fits (N, 3) inputs to (N) rewards: got [5, 2] and [5]"));
  torch::Tensor rewards = torch::zeros({5});
  rewards[2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THAT(ErrorMessage([&] {
                model.Fit(torch::zeros({5, 3}), rewards);
              }),
              ::testing::HasSubstr("the rewards"));
  StepModelOptions bad = Small();
  bad.validation_fraction = 1.0;
  EXPECT_THAT(ErrorMessage([&] { StepModel(StepSignal::kReward, 3, bad, 1); }),
              ::testing::HasSubstr("validation_fraction is 1: expected a number in (0, 1)"));
}

TEST(StepModelTest, ATransitionBufferKeepsRewardsThroughItsFile) {
  TransitionBuffer buffer(1, 1, 4, /*keep_rewards=*/true);
  for (int i = 0; i < 3; ++i) buffer.Add({double(i)}, {0.5}, {double(i + 1)}, false, false, -i);
  const std::string path = (testing::TestTempDir() / "transitions.bin").string();
  buffer.Save(path);
  TransitionBuffer loaded(1, 1, 4, true);
  loaded.Load(path);
  EXPECT_EQ(loaded.rewards()[2], -2.0f);
  EXPECT_TRUE(StepInputs(loaded).equal(StepInputs(buffer)));
  EXPECT_TRUE(StoredRewards(loaded).equal(torch::tensor({0.0f, -1.0f, -2.0f})));
  EXPECT_THAT(ErrorMessage([&] { StoredRewards(TransitionBuffer(1, 1, 4)); }),
              ::testing::HasSubstr("keeps no rewards"));
  EXPECT_THAT(ErrorMessage([&] {
                buffer.Add({0}, {0}, {0}, false, false, std::numeric_limits<double>::infinity());
              }),
              ::testing::HasSubstr("the transition's reward is inf"));
}

// Steps of the same walk that end the episode where the next state passes 1.5: rare (about one
// step in eight), as an episode's last step is.
Steps EndingSteps(int n, std::uint64_t seed) {
  const Steps walk = WalkSteps(n, seed);
  return {walk.inputs, (walk.inputs.select(1, 2) > 1.5).to(torch::kFloat)};
}

TEST(StepModelTest, ATerminationModelGivesProbabilitiesThatSeparateTheEndingSteps) {
  StepModel model(StepSignal::kTermination, 3, Small(), 1);
  const Steps train = EndingSteps(3000, 4), test = EndingSteps(1000, 5);
  const StepFitReport report = model.Fit(train.inputs, train.targets);
  const torch::Tensor p = model.Predict(test.inputs);
  EXPECT_TRUE((p >= 0).logical_and(p <= 1).all().item<bool>());
  const torch::Tensor ends = test.targets > 0.5;
  // Away from the boundary the model is sure; a coin would give a cross entropy of ln 2.
  const torch::Tensor next = test.inputs.select(1, 2);
  EXPECT_GT(p.index({next > 1.8}).min().item<double>(), 0.9);
  EXPECT_LT(p.index({next < 1.2}).max().item<double>(), 0.1);
  EXPECT_LT(report.validation_loss, 0.1);
  EXPECT_EQ(((p > 0.5) == ends).to(torch::kFloat).mean().item<double>() > 0.98, true);

  // Both classes are in the held-out part, however rare the ending steps.
  torch::Tensor few = torch::zeros({40});
  few[3] = 1;
  few[17] = 1;
  const StepFitReport split = model.Fit(WalkSteps(40, 6).inputs, few);
  EXPECT_EQ(split.validation_size, 6 + 1);  // ceil(0.15 x 38) of the others, 1 of the 2 ends
  EXPECT_THAT(ErrorMessage([&] { model.Fit(torch::zeros({4, 3}), torch::full({4}, 0.5)); }),
              ::testing::HasSubstr("the terminations to fit are not all 0 or 1"));
}

TEST(StepModelTest, ATransitionBufferKeepsTheEndingStepsItIsAskedTo) {
  TransitionBuffer plain(1, 1, 8), kept(1, 1, 8, /*keep_rewards=*/false,
                                         /*keep_terminations=*/true);
  for (TransitionBuffer* buffer : {&plain, &kept}) {
    buffer->Add({0}, {0}, {1}, false, false, 0.0, false);
    buffer->Add({1}, {0}, {2}, false, /*episode_end=*/true, 0.0, /*terminated=*/true);
    buffer->Add({2}, {0}, {3}, false, /*episode_end=*/true, 0.0, /*terminated=*/false);  // time
    buffer->Add({3}, {0}, {4}, /*goal_met=*/true, true, 0.0, true);
  }
  EXPECT_EQ(plain.size(), 1);  // the paper's rule: no step that ends an episode
  ASSERT_EQ(kept.size(), 2);   // and the one that ended it by itself
  EXPECT_TRUE(StoredTerminations(kept).equal(torch::tensor({0.0f, 1.0f})));
  const std::string path = (testing::TestTempDir() / "terminations.bin").string();
  kept.Save(path);
  TransitionBuffer loaded(1, 1, 8, false, true);
  loaded.Load(path);
  EXPECT_TRUE(StoredTerminations(loaded).equal(StoredTerminations(kept)));
  EXPECT_THAT(ErrorMessage([&] { StoredTerminations(plain); }),
              ::testing::HasSubstr("keeps no terminations"));
}

}  // namespace
}  // namespace cmbrl
