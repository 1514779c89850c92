#include "cmbrl/models/fused_adam.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <thread>

#include "tests/error_message.h"

namespace cmbrl {
namespace {

// Parameters small and large (the large one is updated on several threads) and a fixed loss.
std::vector<torch::Tensor> MakeParameters() {
  const at::Generator generator = at::detail::createCPUGenerator(7);
  return {torch::randn({3, 5}, generator).requires_grad_(true),
          torch::randn({4, 300, 256}, generator).requires_grad_(true)};
}

void Backward(const std::vector<torch::Tensor>& parameters, int step) {
  torch::Tensor loss = torch::zeros({});
  for (const torch::Tensor& p : parameters) {
    loss = loss + (p - 0.1 * step).pow(2).sum() + p.sin().sum();
  }
  loss.backward();
}

// The optimiser's state saved and read back, as a checkpoint carries it.
torch::serialize::InputArchive SavedState(const FusedAdam& adam) {
  torch::serialize::OutputArchive out;
  adam.Save(out);
  std::stringstream buffer;
  out.save_to(buffer);
  torch::serialize::InputArchive in;
  in.load_from(buffer);
  return in;
}

TEST(FusedAdamTest, FollowsLibTorchsAdam) {
  std::vector<torch::Tensor> ours = MakeParameters();
  std::vector<torch::Tensor> theirs = MakeParameters();
  FusedAdam fused(ours, FusedAdamOptions{});
  torch::optim::Adam reference(theirs, torch::optim::AdamOptions(1e-3));
  for (int step = 0; step < 30; ++step) {
    Backward(ours, step);
    fused.Step();
    reference.zero_grad();
    Backward(theirs, step);
    reference.step();
  }
  EXPECT_EQ(fused.steps(), 30);
  for (size_t i = 0; i < ours.size(); ++i) {
    // The same formula in a different order of float operations: the parameters (up to about
    // 5 in size) have moved by about 0.03 and agree to a few float roundings (5e-7 each).
    EXPECT_LT((ours[i] - theirs[i]).abs().max().item<float>(), 5e-6f) << "parameter " << i;
    EXPECT_GT((ours[i] - MakeParameters()[i]).abs().max().item<float>(), 0.02f);
    EXPECT_FALSE(ours[i].grad().defined()) << "Step() drops the gradient";
  }
}

// A step made member by member, in any order and on several threads, is Step()'s, bit for bit.
TEST(FusedAdamTest, AStepInPartsGivesTheWholeStepsBits) {
  // Every first dimension divisible by 4 (the parts are slices of it).
  const auto make = [] {
    const at::Generator generator = at::detail::createCPUGenerator(9);
    return std::vector<torch::Tensor>{torch::randn({4, 1, 5}, generator).requires_grad_(true),
                                      torch::randn({4, 300, 256}, generator).requires_grad_(true)};
  };
  std::vector<torch::Tensor> whole = make();
  FusedAdam whole_adam(whole, FusedAdamOptions{});
  for (const std::int64_t parts : {1, 2, 4}) {
    std::vector<torch::Tensor> parted = make();
    FusedAdam parted_adam(parted, FusedAdamOptions{});
    std::vector<torch::Tensor> reference = make();
    FusedAdam reference_adam(reference, FusedAdamOptions{});
    for (int step = 0; step < 6; ++step) {
      Backward(reference, step);
      reference_adam.Step();
      Backward(parted, step);
      parted_adam.BeginStep();
      std::vector<std::thread> threads;
      for (std::int64_t part = parts - 1; part >= 0; --part) {
        threads.emplace_back([&parted_adam, part, parts] { parted_adam.StepPart(part, parts); });
      }
      for (std::thread& thread : threads) thread.join();
      parted_adam.EndStep();
    }
    EXPECT_EQ(parted_adam.steps(), 6);
    for (size_t i = 0; i < parted.size(); ++i) {
      EXPECT_TRUE(torch::equal(parted[i], reference[i])) << parts << " parts, parameter " << i;
      EXPECT_FALSE(parted[i].grad().defined()) << "EndStep() drops the gradient";
    }
  }
  // Misuse is refused, not silently wrong.
  Backward(whole, 0);
  EXPECT_THAT(testing::ErrorMessage([&] { whole_adam.StepPart(0, 2); }),
              ::testing::HasSubstr("outside BeginStep() and EndStep()"));
  whole_adam.BeginStep();
  EXPECT_THAT(testing::ErrorMessage([&] { whole_adam.StepPart(0, 3); }),
              ::testing::HasSubstr("a first dimension that 3 divides"));
  EXPECT_THAT(testing::ErrorMessage([&] { whole_adam.Step(); }),
              ::testing::HasSubstr("EndStep() not called"));
  whole_adam.EndStep();
}

TEST(FusedAdamTest, SavedStateResumesToTheSameBits) {
  std::vector<torch::Tensor> straight = MakeParameters();
  FusedAdam straight_adam(straight, FusedAdamOptions{});
  std::vector<torch::Tensor> resumed = MakeParameters();
  FusedAdam first_half(resumed, FusedAdamOptions{});
  for (int step = 0; step < 10; ++step) {
    Backward(straight, step);
    straight_adam.Step();
    if (step < 5) {
      Backward(resumed, step);
      first_half.Step();
    }
  }
  torch::serialize::InputArchive in = SavedState(first_half);
  FusedAdam second_half(resumed, FusedAdamOptions{});
  second_half.Load(in, "the test's archive");
  for (int step = 5; step < 10; ++step) {
    Backward(resumed, step);
    second_half.Step();
  }
  for (size_t i = 0; i < straight.size(); ++i) EXPECT_TRUE(torch::equal(straight[i], resumed[i]));
}

TEST(FusedAdamTest, RefusesStateOfOtherShapes) {
  std::vector<torch::Tensor> parameters = MakeParameters();
  torch::serialize::InputArchive in = SavedState(FusedAdam(parameters, FusedAdamOptions{}));
  std::vector<torch::Tensor> other = {torch::zeros({2, 2}, torch::requires_grad()),
                                      torch::zeros({1}, torch::requires_grad())};
  FusedAdam wrong(other, FusedAdamOptions{});
  EXPECT_THAT(testing::ErrorMessage([&] { wrong.Load(in, "checkpoint.pt"); }),
              ::testing::HasSubstr("Adam state 'exp_avg0' in 'checkpoint.pt' has shape [3, 5], "
                                   "expected [2, 2]"));
}

}  // namespace
}  // namespace cmbrl
