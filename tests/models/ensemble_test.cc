#include "cmbrl/models/ensemble.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cstdio>
#include <filesystem>
#include <thread>
#include <vector>

#include "cmbrl/core/parallel.h"
#include "cmbrl/models/onednn_forward.h"

#include "tests/error_message.h"
#include "tests/temp_path.h"
#include "tests/models/pendulum.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

// Small networks so that fits take a second on two cores; batches of 64 give 4000 transitions
// enough Adam steps in 70 epochs (with the paper's 256 the fit is still falling at epoch 70).
EnsembleOptions SmallOptions() {
  EnsembleOptions options;
  options.hidden_sizes = {64, 64};
  options.batch_size = 64;
  return options;
}

// Held-out pendulum transitions as (E, N, .) tensors for an ensemble of `members`.
struct Batch {
  torch::Tensor states, actions, next;
};
Batch PendulumBatch(int members, int count, std::uint64_t seed) {
  const TransitionBuffer data = testing::PendulumData(count, seed);
  const auto rows = [count](const float* p, int dim) {
    return torch::from_blob(const_cast<float*>(p), {1, count, dim}).clone();
  };
  return {rows(data.states(), 2).expand({members, count, 2}).contiguous(),
          rows(data.actions(), 1).expand({members, count, 1}).contiguous(),
          rows(data.next_states(), 2)};
}

// An ensemble too large for the machine is refused by its sizes before anything is allocated
// (it ended in LibTorch's allocator stack trace).
TEST(EnsembleTest, AnEnsembleTooLargeForTheMachineIsRefusedBySize) {
  EnsembleOptions options;
  options.hidden_sizes = {65536, 65536, 65536};
  const std::string message = ErrorMessage([&] { EnsembleDynamics(4, 2, options, 0); });
  EXPECT_THAT(message, ::testing::HasSubstr("an ensemble of 4 members with hidden layers "
                                            "[65536, 65536, 65536]"));
  EXPECT_THAT(message, ::testing::HasSubstr("more than 80% of this machine's"));
  EXPECT_THAT(message, ::testing::HasSubstr("hidden_sizes"));
  // The count is of weights, gradients and Adam's two moments: 4 floats per parameter.
  options.hidden_sizes = {8};
  options.ensemble_size = 2;
  EXPECT_DOUBLE_EQ(EnsembleParameterBytes(options, 3, 1), 2 * 4 * ((4 + 1) * 8 + (8 + 1) * 3) * 4.0);
}

TEST(EnsembleTest, FitsADampedPendulumStep) {
  EnsembleDynamics ensemble(2, 1, SmallOptions(), 7);
  const EnsembleFitReport report = ensemble.Fit(testing::PendulumData(4000, 1));
  EXPECT_EQ(report.validation_size, 600);  // 15% held out
  EXPECT_EQ(report.train_size, 3400);
  EXPECT_GE(report.epochs, 10);
  // Stated validation error: the normalised MSE falls below 3e-4 (measured 1.0e-4), i.e. the
  // prediction error is under 2% of each state variable's spread.
  EXPECT_LT(report.best_validation_mse, 3e-4);
  // On fresh data, in state units: angle error well under 0.05 rad, velocity under 0.15 rad/s.
  const Batch test = PendulumBatch(4, 1000, 99);
  const torch::Tensor error = (ensemble.Predict(test.states, test.actions) - test.next).abs();
  EXPECT_LT(error.select(2, 0).mean().item<float>(), 0.05f);
  EXPECT_LT(error.select(2, 1).mean().item<float>(), 0.15f);
}

TEST(EnsembleTest, MembersDifferAndAgreeWithinTheData) {
  EnsembleDynamics ensemble(2, 1, SmallOptions(), 3);
  ensemble.Fit(testing::PendulumData(3000, 2));
  const Batch inside = PendulumBatch(4, 500, 5);
  const torch::Tensor prediction = ensemble.Predict(inside.states, inside.actions);  // (4, N, 2)
  const torch::Tensor spread_inside = prediction.std(0).mean();
  // Far outside the training states (angles of 3 pi, velocities of 12) the members disagree
  // more: the epistemic uncertainty the paper's RCE relies on.
  const torch::Tensor far_states = inside.states * 3.0;
  const torch::Tensor spread_outside = ensemble.Predict(far_states, inside.actions).std(0).mean();
  EXPECT_GT(spread_inside.item<float>(), 0.0f);
  EXPECT_GT(spread_outside.item<float>(), 3 * spread_inside.item<float>());
}

TEST(EnsembleTest, SameSeedSameModelDifferentSeedDifferentModel) {
  const TransitionBuffer data = testing::PendulumData(1000, 4);
  EnsembleOptions options = SmallOptions();
  options.max_epochs = 5;
  EnsembleDynamics a(2, 1, options, 11), b(2, 1, options, 11), c(2, 1, options, 12);
  a.Fit(data);
  b.Fit(data);
  c.Fit(data);
  const Batch batch = PendulumBatch(4, 100, 6);
  const torch::Tensor pa = a.Predict(batch.states, batch.actions);
  EXPECT_TRUE(torch::equal(pa, b.Predict(batch.states, batch.actions)));
  EXPECT_FALSE(torch::equal(pa, c.Predict(batch.states, batch.actions)));
}

TEST(EnsembleTest, WarmStartContinuesFromThePreviousFit) {
  const TransitionBuffer data = testing::PendulumData(2000, 8);
  EnsembleOptions options = SmallOptions();
  options.max_epochs = 10;
  EnsembleDynamics ensemble(2, 1, options, 1);
  const EnsembleFitReport first = ensemble.Fit(data);
  const EnsembleFitReport second = ensemble.Fit(data);
  // The second fit starts where the first ended, so it ends clearly lower.
  EXPECT_LT(second.train_mse, 0.7 * first.train_mse);
}

TEST(EnsembleTest, PredictingTheChangeOfStateAlsoFits) {
  EnsembleOptions options = SmallOptions();
  options.predict_delta = true;
  EnsembleDynamics ensemble(2, 1, options, 7);
  ensemble.Fit(testing::PendulumData(4000, 1));
  const Batch test = PendulumBatch(4, 1000, 99);
  const torch::Tensor error = (ensemble.Predict(test.states, test.actions) - test.next).abs();
  // Predicting the small change is easier than the absolute state: tighter than the test above.
  EXPECT_LT(error.select(2, 0).mean().item<float>(), 0.02f);
}

TEST(EnsembleTest, InputNormalisationRoundTrips) {
  EnsembleDynamics ensemble(2, 1, SmallOptions(), 7);
  ensemble.Fit(testing::PendulumData(500, 3));
  const torch::Tensor inputs = torch::tensor({{0.3f, -2.0f, 0.5f}, {-3.0f, 4.0f, -1.0f}});
  const torch::Tensor normalized = ensemble.NormalizeInputs(inputs);
  EXPECT_FALSE(torch::allclose(normalized, inputs));
  EXPECT_TRUE(torch::allclose(ensemble.DenormalizeInputs(normalized), inputs, 0, 1e-5));
}

TEST(EnsembleTest, SaveThenLoadGivesIdenticalPredictionsAndContinuesIdentically) {
  const std::string path = testing::TestTempPath("ensemble_test.pt");
  const TransitionBuffer data = testing::PendulumData(1000, 4);
  EnsembleOptions options = SmallOptions();
  options.max_epochs = 5;
  EnsembleDynamics original(2, 1, options, 21);
  original.Fit(data);
  original.Save(path);
  EnsembleDynamics restored(2, 1, options, 999);  // other seed: everything comes from the file
  restored.Load(path);
  const Batch batch = PendulumBatch(4, 200, 6);
  EXPECT_TRUE(torch::equal(original.Predict(batch.states, batch.actions),
                           restored.Predict(batch.states, batch.actions)));
  // Optimiser and generator states came along: the next fit is the same in both.
  original.Fit(data);
  restored.Fit(data);
  EXPECT_TRUE(torch::equal(original.Predict(batch.states, batch.actions),
                           restored.Predict(batch.states, batch.actions)));
  std::filesystem::remove(path);
}

// A fit paused after every epoch and carried on in another ensemble from the saved file gives
// the uninterrupted fit's model and report, with early stopping in play.
TEST(EnsembleTest, AFitPausedAndCarriedOnFromAFileEqualsAnUninterruptedOne) {
  const std::string path = testing::TestTempPath("ensemble_paused_test.pt");
  const TransitionBuffer data = testing::PendulumData(1000, 4);
  EnsembleOptions options = SmallOptions();
  options.max_epochs = 12;
  options.validate_every = 2;
  options.patience = 2;
  EnsembleDynamics whole(2, 1, options, 21);
  whole.Fit(data);  // a first fit: the second warm-starts, as in a run
  const EnsembleFitReport uninterrupted = whole.Fit(data);
  EnsembleDynamics first(2, 1, options, 21);
  first.Fit(data);
  EnsembleFitReport report = first.Fit(data, nullptr, [] { return true; });
  EXPECT_TRUE(report.paused && first.fit_open());
  EXPECT_EQ(report.epochs, 1);
  first.Save(path);
  int pauses = 1;
  for (;;) {
    EnsembleDynamics next(2, 1, options, 999);  // everything from the file
    next.Load(path);
    EXPECT_TRUE(next.fit_open());
    report = next.Fit(data, nullptr, [] { return true; });
    if (!report.paused) {
      EXPECT_FALSE(next.fit_open());
      const Batch batch = PendulumBatch(4, 200, 6);
      EXPECT_TRUE(torch::equal(next.Predict(batch.states, batch.actions),
                               whole.Predict(batch.states, batch.actions)));
      break;
    }
    ++pauses;
    next.Save(path);
  }
  EXPECT_EQ(pauses, uninterrupted.epochs - 1);  // asked after every epoch but the last
  EXPECT_EQ(report.epochs, uninterrupted.epochs);
  EXPECT_EQ(report.stopped_early, uninterrupted.stopped_early);
  EXPECT_EQ(report.validation_mse, uninterrupted.validation_mse);
  EXPECT_EQ(report.best_validation_mse, uninterrupted.best_validation_mse);
  // An open fit goes on only on its own data.
  EnsembleDynamics open(2, 1, options, 21);
  open.Fit(data, nullptr, [] { return true; });
  EXPECT_THAT(ErrorMessage([&] { open.Fit(testing::PendulumData(900, 4)); }),
              ::testing::HasSubstr("begun on 1000 transitions, but is given 900"));
  std::filesystem::remove(path);
}

TEST(EnsembleTest, LoadingAFileOfOtherShapeIsRefused) {
  const std::string path = testing::TestTempPath("ensemble_shape_test.pt");
  EnsembleDynamics small(2, 1, SmallOptions(), 1);
  small.Save(path);
  EnsembleOptions wider = SmallOptions();
  wider.hidden_sizes = {32, 64};
  EnsembleDynamics other(2, 1, wider, 1);
  EXPECT_THAT(ErrorMessage([&] { other.Load(path); }), ::testing::HasSubstr("has shape"));
  EXPECT_THAT(ErrorMessage([&] { other.Load(path + ".missing"); }),
              ::testing::HasSubstr("could not read an ensemble from"));
  std::filesystem::remove(path);
}

TEST(EnsembleTest, BadInputsAreRefusedByName) {
  EnsembleDynamics ensemble(2, 1, SmallOptions(), 1);
  const torch::Tensor states = torch::zeros({4, 3, 2});
  const torch::Tensor actions = torch::zeros({4, 3, 1});
  EXPECT_EQ(ErrorMessage([&] {
              ensemble.Predict(torch::zeros({4, 3, 5}), actions);
            }),
            "states has shape [4, 3, 5]: expected (..., 2)");
  EXPECT_THAT(ErrorMessage([&] {
                ensemble.Predict(torch::zeros({3, 3, 2}), actions);
              }),
              ::testing::HasSubstr("expected (E=4, N, 2)"));
  torch::Tensor nan_states = states.clone();
  nan_states[1][2][0] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(ErrorMessage([&] { ensemble.Predict(nan_states, actions); }),
            "states has a non-finite value nan at row 5, column 0: expected finite numbers");
  EXPECT_THAT(ErrorMessage([&] { ensemble.Predict(states.to(torch::kDouble), actions); }),
              ::testing::HasSubstr("expected float32"));
  EXPECT_THAT(ErrorMessage([&] { ensemble.Fit(TransitionBuffer(2, 1, 5)); }),
              ::testing::HasSubstr("at least 2 transitions, the buffer has 0"));
  EXPECT_THAT(ErrorMessage([&] { ensemble.Fit(TransitionBuffer(3, 1, 5)); }),
              ::testing::HasSubstr("transition buffer is (3, 1) but the ensemble is (2, 1)"));
}

TEST(EnsembleTest, BadOptionsAreRefusedByName) {
  EnsembleOptions options = SmallOptions();
  options.hidden_sizes = {64, 0};
  EXPECT_EQ(ErrorMessage([&] { EnsembleDynamics(2, 1, options, 1); }),
            "hidden_sizes[1] is 0: expected a width from 1 to 65536");
  options = SmallOptions();
  options.validation_fraction = 1.0;
  EXPECT_THAT(ErrorMessage([&] { EnsembleDynamics(2, 1, options, 1); }),
              ::testing::HasSubstr("validation_fraction is 1"));
  options = SmallOptions();
  options.precision = "fp16";
  EXPECT_EQ(ErrorMessage([&] { EnsembleDynamics(2, 1, options, 1); }),
            "precision is 'fp16': expected fp32, tf32 or bf16");
  options.precision = "tf32";
  EXPECT_THAT(ErrorMessage([&] { EnsembleDynamics(2, 1, options, 1); }),
              ::testing::HasSubstr("precision is tf32 but device is 'cpu'"));
  options = SmallOptions();
  options.device = "tpu";
  EXPECT_THAT(ErrorMessage([&] { EnsembleDynamics(2, 1, options, 1); }),
              ::testing::HasSubstr("device 'tpu'"));
}

// LibTorch's bf16 path (oneDNN's is OnednnBfloat16StaysClose).
TEST(EnsembleTest, Bfloat16PredictionsStayCloseAndTrainingStaysFloat32) {
  const TransitionBuffer data = testing::PendulumData(2000, 4);
  EnsembleOptions options = SmallOptions();
  options.max_epochs = 10;
  options.backend = "libtorch";
  EnsembleDynamics full(2, 1, options, 5);
  options.precision = "bf16";
  EnsembleDynamics reduced(2, 1, options, 5);
  full.Fit(data);
  reduced.Fit(data);
  const Batch batch = PendulumBatch(4, 300, 6);
  const torch::Tensor exact = full.Predict(batch.states, batch.actions);
  const torch::Tensor rounded = reduced.Predict(batch.states, batch.actions);
  EXPECT_EQ(rounded.scalar_type(), torch::kFloat);
  // bfloat16 keeps 8 mantissa bits: relative errors of a few 1e-3, not zero.
  const double error = ((rounded - exact).abs().mean() / exact.abs().mean()).item<double>();
  EXPECT_GT(error, 1e-5);
  EXPECT_LT(error, 2e-2);
  // Training ran in float32 in both: saving the bf16 model and loading it into the fp32 one
  // reproduces the fp32 predictions exactly.
  const std::string path = testing::TestTempPath("bf16_ensemble.pt");
  reduced.Save(path);
  options.precision = "fp32";
  EnsembleDynamics reloaded(2, 1, options, 9);
  reloaded.Load(path);
  EXPECT_TRUE(torch::equal(reloaded.Predict(batch.states, batch.actions), exact));
  std::filesystem::remove(path);
}

// The two CPU backends on the same weights: a LibTorch ensemble fitted, and one of `backend` and
// `precision` that loads its file (each backend trains with its own products, so fits of the
// same seed agree only to rounding; the predictions are compared on equal weights).
struct BackendPair {
  std::unique_ptr<EnsembleDynamics> reference, other;
};
BackendPair FittedPair(const std::string& backend, const std::string& precision, bool delta) {
  EnsembleOptions options = SmallOptions();
  options.max_epochs = 10;
  options.predict_delta = delta;
  options.backend = "libtorch";
  BackendPair pair;
  pair.reference = std::make_unique<EnsembleDynamics>(2, 1, options, 5);
  options.backend = backend;
  options.precision = precision;
  pair.other = std::make_unique<EnsembleDynamics>(2, 1, options, 5);
  pair.reference->Fit(testing::PendulumData(2000, 4));
  const std::string path = testing::TestTempPath("backend_pair.pt");
  pair.reference->Save(path);
  pair.other->Load(path);
  std::filesystem::remove(path);
  return pair;
}

double RelativeError(const torch::Tensor& value, const torch::Tensor& exact) {
  return ((value - exact).abs().mean() / exact.abs().mean()).item<double>();
}

#define SKIP_WITHOUT_ONEDNN(bf16) \
  if (std::string why; !OnednnForwardAvailable(bf16, &why)) GTEST_SKIP() << why;

TEST(EnsembleTest, OnednnFloat32AgreesWithLibTorch) {
  SKIP_WITHOUT_ONEDNN(false);
  for (const bool delta : {false, true}) {
    SCOPED_TRACE(delta ? "predicting the change" : "predicting the next state");
    const BackendPair pair = FittedPair("onednn", "fp32", delta);
    EXPECT_EQ(pair.reference->backend(), "libtorch");
    EXPECT_EQ(pair.other->backend(), "onednn");
    // One primitive set per batch size; the last crosses a block.
    for (const int rows : {1, 7, static_cast<int>(OnednnPredictionBlockRows()) + 44}) {
      const Batch batch = PendulumBatch(4, rows, 6);
      const torch::Tensor exact = pair.reference->Predict(batch.states, batch.actions);
      const torch::Tensor fast = pair.other->Predict(batch.states, batch.actions);
      ASSERT_EQ(fast.sizes(), exact.sizes());
      // Stated tolerance: float32 sums in another order and the output normaliser folded into
      // the last layer: agreement to 1e-5 of the values (measured below 1e-6).
      EXPECT_TRUE(torch::allclose(fast, exact, 1e-5, 1e-5)) << (fast - exact).abs().max();
    }
  }
}

TEST(EnsembleTest, OnednnBfloat16StaysClose) {
  SKIP_WITHOUT_ONEDNN(true);
  const BackendPair pair = FittedPair("onednn", "bf16", false);
  const Batch batch = PendulumBatch(4, 300, 6);
  const torch::Tensor exact = pair.reference->Predict(batch.states, batch.actions);
  const torch::Tensor rounded = pair.other->Predict(batch.states, batch.actions);
  EXPECT_EQ(rounded.scalar_type(), torch::kFloat);
  // The same bound as LibTorch's bf16 path: rounded (not zero) but within 2e-2.
  const double error = RelativeError(rounded, exact);
  EXPECT_GT(error, 1e-5);
  EXPECT_LT(error, 2e-2);
}

TEST(EnsembleTest, OnednnFloat32RepeatsExactly) {
  SKIP_WITHOUT_ONEDNN(false);
  const BackendPair pair = FittedPair("onednn", "fp32", true);
  // A full block and a one-row tail per member: two primitive sets.
  const Batch batch = PendulumBatch(4, static_cast<int>(OnednnPredictionBlockRows()) + 1, 8);
  const torch::Tensor first = pair.other->Predict(batch.states, batch.actions);
  pair.other->Predict(batch.states.narrow(1, 0, 3), batch.actions.narrow(1, 0, 3));
  EXPECT_TRUE(torch::equal(pair.other->Predict(batch.states, batch.actions), first));
  // Another ensemble of the same seed, and the same model saved and loaded, predict the same bits.
  const std::string path = testing::TestTempPath("onednn_ensemble.pt");
  pair.other->Save(path);
  EnsembleOptions options = pair.other->options();
  EnsembleDynamics loaded(2, 1, options, 99);
  loaded.Load(path);
  EXPECT_TRUE(torch::equal(loaded.Predict(batch.states, batch.actions), first));
  std::filesystem::remove(path);
  // Refitting replaces the weights the primitives read: the predictions change.
  pair.other->Fit(testing::PendulumData(500, 9));
  EXPECT_FALSE(torch::equal(pair.other->Predict(batch.states, batch.actions), first));
}

TEST(EnsembleTest, OnednnPredictsConcurrently) {
  SKIP_WITHOUT_ONEDNN(false);
  const BackendPair pair = FittedPair("onednn", "fp32", false);
  const std::vector<int> sizes = {5, 64, 200, 64};
  std::vector<torch::Tensor> serial, parallel(sizes.size());
  std::vector<Batch> batches;
  for (const int rows : sizes) batches.push_back(PendulumBatch(4, rows, rows));
  std::vector<std::thread> threads;
  for (size_t i = 0; i < sizes.size(); ++i) {
    threads.emplace_back([&, i] {
      for (int repeat = 0; repeat < 20; ++repeat) {
        parallel[i] = pair.other->Predict(batches[i].states, batches[i].actions);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (size_t i = 0; i < sizes.size(); ++i) {
    EXPECT_TRUE(torch::equal(parallel[i], pair.other->Predict(batches[i].states,
                                                              batches[i].actions)));
  }
}

// A prediction is cut into tasks of fixed shape: its bits are the same on one core as on all,
// and whichever thread asks (the OpenMP thread count differs from thread to thread).
TEST(EnsembleTest, OnednnBitsDoNotDependOnTheCores) {
  SKIP_WITHOUT_ONEDNN(false);
  const std::vector<int> cpus = AllowedCpus();
  if (cpus.size() < 2) GTEST_SKIP() << "one CPU allowed: nothing to compare";
  const BackendPair pair = FittedPair("onednn", "fp32", false);
  // Two full blocks and a shorter one per member.
  const std::int64_t block = OnednnPredictionBlockRows();
  const Batch batch = PendulumBatch(4, static_cast<int>(2 * block + block / 3), 12);
  const torch::Tensor on_all = pair.other->Predict(batch.states, batch.actions);
  torch::Tensor on_one, on_another_thread;
  std::thread([&] {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpus.front(), &one);
    ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
    ASSERT_EQ(CoreCount(), 1);
    on_one = pair.other->Predict(batch.states, batch.actions);
  }).join();
  std::thread([&] { on_another_thread = pair.other->Predict(batch.states, batch.actions); })
      .join();
  EXPECT_TRUE(torch::equal(on_one, on_all));
  EXPECT_TRUE(torch::equal(on_another_thread, on_all));
}

TEST(EnsembleTest, BackendIsCheckedByName) {
  EnsembleOptions options = SmallOptions();
  options.backend = "mkl";
  EXPECT_EQ(ErrorMessage([&] { EnsembleDynamics(2, 1, options, 1); }),
            "backend is 'mkl': expected auto, libtorch or onednn");
  options.backend = "onednn";
  options.device = "cuda";
  EXPECT_EQ(ErrorMessage([&] { EnsembleDynamics(2, 1, options, 1); }),
            "backend is onednn but device is 'cuda': oneDNN predicts on the CPU; use libtorch or "
            "auto on CUDA");
  options.device = "cpu";
  options.backend = "auto";
  EXPECT_EQ(EnsembleDynamics(2, 1, options, 1).backend(),
            OnednnForwardAvailable(false) ? "onednn" : "libtorch");
}

TEST(EnsembleTest, CpuAndCudaAgree) {
  if (!torch::cuda::is_available()) GTEST_SKIP() << "this LibTorch has no CUDA or sees no GPU";
  const TransitionBuffer data = testing::PendulumData(2000, 4);
  EnsembleOptions options = SmallOptions();
  options.max_epochs = 10;
  EnsembleDynamics cpu(2, 1, options, 5);
  options.device = "cuda";
  EnsembleDynamics cuda(2, 1, options, 5);
  cpu.Fit(data);
  cuda.Fit(data);
  const Batch batch = PendulumBatch(4, 300, 6);
  const torch::Tensor on_cpu = cpu.Predict(batch.states, batch.actions);
  const torch::Tensor on_cuda = cuda.Predict(batch.states.cuda(), batch.actions.cuda()).cpu();
  // Same draws (CPU generator), same arithmetic up to float rounding in 10 epochs of Adam
  // (cuBLAS sums in another order): agreement to 1e-3 of values of order 1.
  EXPECT_TRUE(torch::allclose(on_cpu, on_cuda, 1e-3, 1e-3));
}

}  // namespace
}  // namespace cmbrl
