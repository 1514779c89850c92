#include "cmbrl/models/reward_model.h"

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
  torch::Tensor inputs, rewards;
};

Steps WalkSteps(int n, std::uint64_t seed) {
  at::Generator generator = at::detail::createCPUGenerator(seed);
  const torch::Tensor state = torch::rand({n, 1}, generator) * 4 - 2;
  const torch::Tensor action = torch::rand({n, 1}, generator) * 2 - 1;
  const torch::Tensor next = state + 0.1 * action;
  return {torch::cat({state, action, next}, 1), -(next.squeeze(1) - 1).abs()};
}

RewardModelOptions Small() {
  RewardModelOptions options;
  options.hidden_sizes = {32, 32};
  options.max_epochs = 60;
  return options;
}

TEST(RewardModelTest, LearnsARewardWellBelowItsSpreadOnHeldOutSteps) {
  RewardModel model(3, Small(), 1);
  const Steps train = WalkSteps(3000, 1), test = WalkSteps(500, 2);
  const RewardFitReport report = model.Fit(train.inputs, train.rewards);
  EXPECT_GT(report.epochs, 0);
  EXPECT_EQ(report.train_size + report.validation_size, 3000);
  const double variance = test.rewards.var(0, false).item<double>();
  const double mse = (model.Predict(test.inputs) - test.rewards).pow(2).mean().item<double>();
  EXPECT_LT(mse, 0.05 * variance) << "held-out MSE " << mse << ", variance " << variance;
  EXPECT_LT(report.validation_mse, 0.05 * variance);
  // Any leading shape: (2, 5, 3) inputs give (2, 5) rewards.
  EXPECT_EQ(model.Predict(test.inputs.slice(0, 0, 10).view({2, 5, 3})).sizes(),
            (std::vector<std::int64_t>{2, 5}));
}

TEST(RewardModelTest, TheSameSeedFitsTheSameModelAndAFileCarriesIt) {
  const Steps steps = WalkSteps(400, 3);
  RewardModel a(3, Small(), 7), b(3, Small(), 7), other(3, Small(), 8);
  EXPECT_TRUE(a.Predict(steps.inputs).eq(0).all().item<bool>());  // no fit yet: zeros
  a.Fit(steps.inputs, steps.rewards);
  b.Fit(steps.inputs, steps.rewards);
  other.Fit(steps.inputs, steps.rewards);
  EXPECT_TRUE(a.Predict(steps.inputs).equal(b.Predict(steps.inputs)));
  EXPECT_FALSE(a.Predict(steps.inputs).equal(other.Predict(steps.inputs)));

  // Saved and loaded, it predicts the same, and its next fit is the one `a` makes (the
  // generator travels with it).
  const std::string path = (testing::TestTempDir() / "reward_model.pt").string();
  a.Save(path);
  RewardModel loaded(3, Small(), 99);
  loaded.Load(path);
  EXPECT_TRUE(loaded.Predict(steps.inputs).equal(a.Predict(steps.inputs)));
  a.Fit(steps.inputs, steps.rewards);
  loaded.Fit(steps.inputs, steps.rewards);
  EXPECT_TRUE(loaded.Predict(steps.inputs).equal(a.Predict(steps.inputs)));

  RewardModelOptions wider = Small();
  wider.hidden_sizes = {64, 32};
  RewardModel mismatched(3, wider, 1);
  EXPECT_THAT(ErrorMessage([&] { mismatched.Load(path); }),
              ::testing::HasSubstr("this model's is [3, 64] (other hidden_sizes)"));
  EXPECT_THAT(ErrorMessage([&] { RewardModel(4, Small(), 1).Load(path); }),
              ::testing::HasSubstr("holds a reward model of 3 inputs"));
}

TEST(RewardModelTest, BadInputsAndOptionsAreNamed) {
  RewardModel model(3, Small(), 1);
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
  RewardModelOptions bad = Small();
  bad.validation_fraction = 1.0;
  EXPECT_THAT(ErrorMessage([&] { RewardModel(3, bad, 1); }),
              ::testing::HasSubstr("validation_fraction is 1: expected a number in (0, 1)"));
}

TEST(RewardModelTest, ATransitionBufferKeepsRewardsThroughItsFile) {
  TransitionBuffer buffer(1, 1, 4, /*keep_rewards=*/true);
  for (int i = 0; i < 3; ++i) buffer.Add({double(i)}, {0.5}, {double(i + 1)}, false, false, -i);
  const std::string path = (testing::TestTempDir() / "transitions.bin").string();
  buffer.Save(path);
  TransitionBuffer loaded(1, 1, 4, true);
  loaded.Load(path);
  EXPECT_EQ(loaded.rewards()[2], -2.0f);
  EXPECT_TRUE(RewardInputs(loaded).equal(RewardInputs(buffer)));
  EXPECT_TRUE(StoredRewards(loaded).equal(torch::tensor({0.0f, -1.0f, -2.0f})));
  EXPECT_THAT(ErrorMessage([&] { StoredRewards(TransitionBuffer(1, 1, 4)); }),
              ::testing::HasSubstr("keeps no rewards"));
  EXPECT_THAT(ErrorMessage([&] {
                buffer.Add({0}, {0}, {0}, false, false, std::numeric_limits<double>::infinity());
              }),
              ::testing::HasSubstr("the transition's reward is inf"));
}

}  // namespace
}  // namespace cmbrl
