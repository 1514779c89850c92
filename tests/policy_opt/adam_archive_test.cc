// Adam's moments in a checkpoint archive (policy_opt/adam_archive.cc): read back, the next step is
// the uninterrupted optimiser's, in this build's form and in LibTorch's (earlier builds').
#include "cmbrl/policy_opt/adam_archive.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "tests/error_message.h"

namespace cmbrl {
namespace {

// Two parameters, a (2, 3) weight and a (3) bias, and their Adam optimiser.
struct Problem {
  std::vector<torch::Tensor> params;
  std::unique_ptr<torch::optim::Adam> adam;

  explicit Problem(bool amsgrad = false, std::vector<int64_t> weight_shape = {2, 3}) {
    params = {torch::linspace(-1.0, 1.0, 6, torch::kFloat64).reshape(weight_shape),
              torch::tensor({0.5, -0.25, 1.0}, torch::kFloat64)};
    for (torch::Tensor& p : params) p.requires_grad_(true);
    adam = std::make_unique<torch::optim::Adam>(params,
                                                torch::optim::AdamOptions(0.01).amsgrad(amsgrad));
  }

  // The parameters' values of `other`, copied (the optimiser's state is not).
  void CopyValuesFrom(const Problem& other) {
    const torch::NoGradGuard no_grad;
    for (size_t i = 0; i < params.size(); ++i) params[i].copy_(other.params[i]);
  }

  // Step k: gradients that depend on the parameters and on k; `bias` false leaves the bias
  // without one (Adam then does not step it).
  void Step(int k, bool bias = true) {
    for (size_t i = 0; i < params.size(); ++i) {
      if (i == 1 && !bias) {
        params[i].mutable_grad() = torch::Tensor();
        continue;
      }
      params[i].mutable_grad() = torch::sin(params[i].detach() * (k + 1)) + 0.1 * k;
    }
    adam->step();
  }
};

std::string Bytes(torch::serialize::OutputArchive& archive) {
  std::ostringstream out;
  archive.save_to(out);
  return out.str();
}

torch::serialize::InputArchive Archive(const std::string& bytes) {
  std::istringstream in(bytes);
  torch::serialize::InputArchive archive;
  archive.load_from(in);
  return archive;
}

std::string Written(const Problem& problem) {
  torch::serialize::OutputArchive archive;
  WriteAdamMoments(archive, "policy_adam", *problem.adam);
  return Bytes(archive);
}

// A problem of `whole`'s parameter values whose optimiser read the moments in `bytes`.
Problem Resumed(const Problem& whole, const std::string& bytes, bool amsgrad = false) {
  Problem resumed(amsgrad);
  resumed.CopyValuesFrom(whole);
  torch::serialize::InputArchive archive = Archive(bytes);
  ReadAdamMoments(archive, "policy_adam", "policy_optimizer", *resumed.adam, "networks.pt");
  return resumed;
}

// Steps 3 and 4 of both problems give the same parameters, bit for bit.
void ExpectSameNextSteps(Problem& whole, Problem& resumed) {
  for (int k = 3; k < 5; ++k) {
    whole.Step(k);
    resumed.Step(k);
  }
  for (size_t i = 0; i < whole.params.size(); ++i) {
    EXPECT_TRUE(torch::equal(whole.params[i], resumed.params[i])) << "parameter " << i;
  }
}

TEST(AdamArchiveTest, MomentsReadBackGiveTheUninterruptedOptimisersNextSteps) {
  for (const bool amsgrad : {false, true}) {
    SCOPED_TRACE(amsgrad ? "amsgrad" : "adam");
    Problem whole(amsgrad);
    for (int k = 0; k < 3; ++k) whole.Step(k);
    Problem resumed = Resumed(whole, Written(whole), amsgrad);
    Problem fresh(amsgrad);
    fresh.CopyValuesFrom(whole);
    ExpectSameNextSteps(whole, resumed);
    // Without the moments the steps differ: the comparison above can fail.
    for (int k = 3; k < 5; ++k) fresh.Step(k);
    EXPECT_FALSE(torch::equal(whole.params[0], fresh.params[0]));
  }
}

TEST(AdamArchiveTest, TheSameNumbersWriteTheSameBytes) {
  Problem a, b;  // other tensors, at other addresses
  for (int k = 0; k < 3; ++k) {
    a.Step(k);
    b.Step(k);
  }
  EXPECT_EQ(Written(a), Written(b));
  b.Step(3);
  EXPECT_NE(Written(a), Written(b));
}

// A checkpoint of an earlier build holds LibTorch's own save of the optimiser under another
// name; its moments are matched to the parameters by their place.
TEST(AdamArchiveTest, AnEarlierBuildsCheckpointInLibTorchsFormIsRead) {
  Problem whole;
  for (int k = 0; k < 3; ++k) whole.Step(k);
  torch::serialize::OutputArchive old_moments, archive;
  whole.adam->save(old_moments);
  archive.write("policy_optimizer", old_moments);
  const std::string bytes = Bytes(archive);

  Problem resumed = Resumed(whole, bytes);
  // Read so, it is written in this build's form, the uninterrupted optimiser's bytes.
  EXPECT_EQ(Written(resumed), Written(whole));
  ExpectSameNextSteps(whole, resumed);
}

TEST(AdamArchiveTest, AParameterNotYetSteppedHasNoMomentsBeforeOrAfter) {
  Problem whole;
  for (int k = 0; k < 3; ++k) whole.Step(k, /*bias=*/false);
  ASSERT_EQ(whole.adam->state().size(), 1u);
  Problem resumed = Resumed(whole, Written(whole));
  EXPECT_EQ(resumed.adam->state().size(), 1u);
  ExpectSameNextSteps(whole, resumed);
}

TEST(AdamArchiveTest, NoMomentsOrMomentsOfAnotherShapeAreNamed) {
  Problem problem;
  torch::serialize::OutputArchive empty;
  empty.write("generator", torch::zeros({1}));
  torch::serialize::InputArchive none = Archive(Bytes(empty));
  EXPECT_THAT(
      testing::ErrorMessage([&] {
        ReadAdamMoments(none, "value_adam", "value_optimizer", *problem.adam,
                        "run/checkpoint/networks.pt");
      }),
      ::testing::HasSubstr("'run/checkpoint/networks.pt' holds no optimiser state for value_adam"));

  Problem other_shape(/*amsgrad=*/false, {3, 2});
  other_shape.Step(0);
  torch::serialize::InputArchive wrong = Archive(Written(other_shape));
  EXPECT_THAT(testing::ErrorMessage([&] {
                ReadAdamMoments(wrong, "policy_adam", "policy_optimizer", *problem.adam,
                                "networks.pt");
              }),
              ::testing::HasSubstr("'networks.pt' is damaged: policy_adam's moments of parameter "
                                   "0 are missing or of another shape"));
}

}  // namespace
}  // namespace cmbrl
