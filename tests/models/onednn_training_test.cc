#include "cmbrl/models/onednn_training.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <thread>
#include <vector>

#include "cmbrl/core/cpu_features.h"
#include "cmbrl/core/parallel.h"
#include "cmbrl/models/ensemble.h"
#include "cmbrl/models/onednn_forward.h"
#include "tests/models/pendulum.h"

namespace cmbrl {
namespace {

#define SKIP_WITHOUT_ONEDNN() \
  if (std::string why; !OnednnForwardAvailable(false, &why)) GTEST_SKIP() << why;

// Random parameters of an ensemble of `members` with the given layer sizes, as EnsembleDynamics
// holds them: weights (E, in, out), biases (E, 1, out), leaves that take gradients.
struct Parameters {
  std::vector<torch::Tensor> weights, biases;
};
Parameters RandomParameters(int members, const std::vector<std::int64_t>& sizes,
                            std::uint64_t seed) {
  torch::manual_seed(seed);
  Parameters p;
  for (size_t l = 0; l + 1 < sizes.size(); ++l) {
    p.weights.push_back((torch::randn({members, sizes[l], sizes[l + 1]}) * 0.3).requires_grad_());
    p.biases.push_back((torch::randn({members, 1, sizes[l + 1]}) * 0.1).requires_grad_());
  }
  return p;
}

// The loss and gradients as EnsembleDynamics's LibTorch path takes them: autograd over batched
// products, the sum over members of each member's mean squared error.
double AutogradLoss(Parameters& p, const torch::Tensor& x, const torch::Tensor& y,
                    const torch::Tensor& batch) {
  torch::Tensor h = x.index({batch});
  for (size_t l = 0; l < p.weights.size(); ++l) {
    h = torch::baddbmm(p.biases[l], h, p.weights[l]);
    if (l + 1 < p.weights.size()) h = torch::relu(h);
  }
  const torch::Tensor loss = (h - y.index({batch})).pow(2).mean({1, 2}).sum();
  loss.backward();
  return loss.item<double>();
}

// The oneDNN gradients agree with autograd's, for full and short batches and networks of one and
// of three hidden layers; the parameters themselves are left alone.
TEST(OnednnTrainingTest, GradientsAgreeWithAutograd) {
  SKIP_WITHOUT_ONEDNN();
  for (const std::vector<std::int64_t>& sizes :
       std::vector<std::vector<std::int64_t>>{{5, 16, 3}, {7, 32, 24, 32, 6}}) {
    const int members = 3;
    OnednnEnsembleTraining training(sizes);
    const torch::Tensor x = torch::randn({90, sizes.front()});
    const torch::Tensor y = torch::randn({90, sizes.back()});
    for (const int rows : {20, 7, 20}) {  // a second batch size, then the first plan again
      SCOPED_TRACE(::testing::Message() << sizes.size() - 1 << " layers, batch " << rows);
      const torch::Tensor batch = torch::randint(0, 90, {members, rows}, torch::kLong);
      Parameters exact = RandomParameters(members, sizes, rows);
      Parameters fast = RandomParameters(members, sizes, rows);
      const double exact_loss = AutogradLoss(exact, x, y, batch);
      const std::vector<torch::Tensor> weights_before = {fast.weights[0].detach().clone()};
      const double loss = training.Gradients(fast.weights, fast.biases, x, y, batch);
      // Stated tolerance: float32 sums in other orders, 1e-5 relative.
      EXPECT_NEAR(loss, exact_loss, 1e-5 * exact_loss);
      for (size_t l = 0; l < exact.weights.size(); ++l) {
        SCOPED_TRACE(::testing::Message() << "layer " << l);
        const torch::Tensor& gw = fast.weights[l].grad();
        const torch::Tensor& gb = fast.biases[l].grad();
        ASSERT_TRUE(gw.defined() && gb.defined());
        ASSERT_EQ(gw.sizes(), exact.weights[l].grad().sizes());
        ASSERT_EQ(gb.sizes(), exact.biases[l].grad().sizes());
        EXPECT_TRUE(torch::allclose(gw, exact.weights[l].grad(), 1e-4, 1e-6))
            << (gw - exact.weights[l].grad()).abs().max();
        EXPECT_TRUE(torch::allclose(gb, exact.biases[l].grad(), 1e-4, 1e-6))
            << (gb - exact.biases[l].grad()).abs().max();
      }
      EXPECT_TRUE(torch::equal(fast.weights[0].detach(), weights_before[0]));
    }
  }
}

EnsembleOptions OnednnOptions() {
  EnsembleOptions options;
  options.hidden_sizes = {64, 64};
  options.batch_size = 64;
  options.max_epochs = 10;
  options.backend = "onednn";
  return options;
}

torch::Tensor PredictionsOf(const EnsembleDynamics& model) {
  torch::manual_seed(3);
  const torch::Tensor states = torch::randn({4, 50, 2});
  const torch::Tensor actions = torch::randn({4, 50, 1});
  return model.Predict(states, actions);
}

// A oneDNN fit repeats bit for bit: from the same seed, on one core as on all, and from another
// thread (each member's products run as one single-threaded task).
TEST(OnednnTrainingTest, FitsRepeatExactlyWhateverTheCores) {
  SKIP_WITHOUT_ONEDNN();
  const TransitionBuffer data = testing::PendulumData(1500, 4);
  EnsembleDynamics first(2, 1, OnednnOptions(), 5);
  const EnsembleFitReport report = first.Fit(data);
  EnsembleDynamics again(2, 1, OnednnOptions(), 5);
  EXPECT_EQ(again.Fit(data).train_mse, report.train_mse);
  EXPECT_TRUE(torch::equal(PredictionsOf(again), PredictionsOf(first)));
  const std::vector<int> cpus = AllowedCpus();
  torch::Tensor on_one;
  std::thread([&] {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpus.front(), &one);
    ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
    EnsembleDynamics pinned(2, 1, OnednnOptions(), 5);
    pinned.Fit(data);
    on_one = PredictionsOf(pinned);
  }).join();
  EXPECT_TRUE(torch::equal(on_one, PredictionsOf(first)));
}

// A oneDNN fit and a LibTorch fit from the same seed take the same batches and differ only by
// rounding: their errors and predictions agree closely.
TEST(OnednnTrainingTest, FitsAgreeWithLibTorchFits) {
  SKIP_WITHOUT_ONEDNN();
  const TransitionBuffer data = testing::PendulumData(1500, 4);
  EnsembleOptions options = OnednnOptions();
  options.max_epochs = 3;
  EnsembleDynamics fast(2, 1, options, 5);
  options.backend = "libtorch";
  EnsembleDynamics exact(2, 1, options, 5);
  const EnsembleFitReport fast_report = fast.Fit(data);
  const EnsembleFitReport exact_report = exact.Fit(data);
  EXPECT_EQ(fast_report.epochs, exact_report.epochs);
  EXPECT_NEAR(fast_report.train_mse, exact_report.train_mse, 1e-3 * exact_report.train_mse);
  const torch::Tensor a = PredictionsOf(fast), b = PredictionsOf(exact);
  const double relative = ((a - b).abs().mean() / b.abs().mean()).item<double>();
  EXPECT_LT(relative, 1e-3);
  // Another seed: the oneDNN fit is no copy of the LibTorch one that happens to agree.
  EnsembleDynamics other(2, 1, OnednnOptions(), 6);
  other.Fit(data);
  EXPECT_GT(((PredictionsOf(other) - b).abs().mean() / b.abs().mean()).item<double>(), 1e-3);
}

// Who trains: auto sends the training products to oneDNN at any width on a CPU with AVX-512,
// elsewhere only for layers at most 256 wide; onednn always; libtorch never. The rule is fixed by
// the config and the CPU's vector ISA, never by a timing.
TEST(OnednnTrainingTest, AutoTrainsThroughOnednnWhereItIsFaster) {
  SKIP_WITHOUT_ONEDNN();
  EnsembleOptions options = OnednnOptions();
  const auto trainer = [&](const std::string& backend, std::vector<int> hidden) {
    options.backend = backend;
    options.hidden_sizes = std::move(hidden);
    const EnsembleDynamics model(2, 1, options, 1);
    return model.backend() + "/" + model.training_backend();
  };
  EXPECT_EQ(trainer("auto", {256, 256, 256}), "onednn/onednn");
  const std::string wide = CpuHasAvx512() ? "onednn/onednn" : "onednn/libtorch";
  EXPECT_EQ(trainer("auto", {256, 257}), wide);
  EXPECT_EQ(trainer("auto", {512, 512, 512}), wide);
  EXPECT_EQ(trainer("auto", {256, 1025}), wide);
  EXPECT_EQ(trainer("auto", {1024, 1024, 1024}), wide);
  EXPECT_EQ(trainer("onednn", {1024}), "onednn/onednn");
  EXPECT_EQ(trainer("libtorch", {64}), "libtorch/libtorch");
}

}  // namespace
}  // namespace cmbrl
