#include "cmbrl/models/xgboost_cost_model.h"

#include <ATen/record_function.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "cmbrl/models/tree_ensemble_tensor.h"
#include "tests/error_message.h"
#include "tests/models/hazard_data.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;
using testing::kHazardStateDim;

// One trained model shared by the tests of this file (a fit takes about a second).
class XgbCostModelTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // Imbalanced 1:20 as the buffers fill in the task; the fit then uses every unsafe state and
    // the newest 3 n_unsafe + 1 safe ones.
    const testing::HazardData data = testing::MakeHazardData(40000, 2000, 1);
    buffer_ = new LabeledStateBuffer(kHazardStateDim, 50000, 10000);
    for (int i = 0; i < data.safe_count; ++i) {
      buffer_->Add(std::vector<double>(data.safe.begin() + i * kHazardStateDim,
                                       data.safe.begin() + (i + 1) * kHazardStateDim),
                   false);
    }
    for (int i = 0; i < data.unsafe_count; ++i) {
      buffer_->Add(std::vector<double>(data.unsafe.begin() + i * kHazardStateDim,
                                       data.unsafe.begin() + (i + 1) * kHazardStateDim),
                   true);
    }
    model_ = new XgbCostModel(kHazardStateDim, XgbCostModelOptions{}, 3);
    report_ = model_->Fit(*buffer_);
    test_ = new testing::HazardData(testing::MakeHazardData(10000, 2000, 2));
  }
  static void TearDownTestSuite() {
    delete model_;
    delete buffer_;
    delete test_;
  }
  static LabeledStateBuffer* buffer_;
  static XgbCostModel* model_;
  static CostFitReport report_;
  static testing::HazardData* test_;
};
LabeledStateBuffer* XgbCostModelTest::buffer_ = nullptr;
XgbCostModel* XgbCostModelTest::model_ = nullptr;
CostFitReport XgbCostModelTest::report_;
testing::HazardData* XgbCostModelTest::test_ = nullptr;

TEST_F(XgbCostModelTest, FitUsesEveryUnsafeAndThreeTimesAsManySafeStates) {
  EXPECT_TRUE(report_.trained);
  EXPECT_EQ(report_.unsafe_used, 2000);
  EXPECT_EQ(report_.safe_used, 6001);
  EXPECT_EQ(report_.trees, 400);
  EXPECT_GT(report_.safe_accuracy, 0.97);
  EXPECT_GT(report_.unsafe_accuracy, 0.97);
  EXPECT_LE(model_->trees().max_depth(), 8);
}

TEST_F(XgbCostModelTest, RecallOnHeldOutUnsafeStatesIsAtLeastNinetyFivePercent) {
  const std::vector<std::uint8_t> unsafe =
      model_->PredictRows(test_->unsafe.data(), test_->unsafe_count);
  const std::vector<std::uint8_t> safe = model_->PredictRows(test_->safe.data(), test_->safe_count);
  int caught = 0, false_alarms = 0;
  for (std::uint8_t v : unsafe) caught += v;
  for (std::uint8_t v : safe) false_alarms += v;
  // Measured: 98.3% recall, 1.4% false alarms on 10,000 held-out safe states.
  EXPECT_GE(caught, 0.95 * test_->unsafe_count);
  EXPECT_LE(false_alarms, 0.05 * test_->safe_count);
}

TEST_F(XgbCostModelTest, FlatTreesEqualXgboostBitForBit) {
  const std::vector<float> ours = model_->Margins(test_->safe.data(), 3000);
  const std::vector<float> theirs = model_->XgboostMargins(test_->safe.data(), 3000);
  EXPECT_EQ(ours, theirs);
  const std::vector<float> ours_unsafe = model_->Margins(test_->unsafe.data(), 2000);
  EXPECT_EQ(ours_unsafe, model_->XgboostMargins(test_->unsafe.data(), 2000));
}

// A row count that is not a multiple of the 32-row block, with some missing values (NaN), which
// XGBoost sends along each node's default direction.
std::vector<float> RowsWithMissingValues(const std::vector<float>& source, int rows) {
  std::vector<float> states(source.begin(), source.begin() + rows * kHazardStateDim);
  for (int i = 0; i < rows; i += 7) states[i * kHazardStateDim + (i % kHazardStateDim)] = NAN;
  return states;
}

TEST_F(XgbCostModelTest, EveryTreeKernelAndThreadCountGivesXgboostsBits) {
  const int rows = 2001;
  const std::vector<float> states = RowsWithMissingValues(test_->safe, rows);
  const std::vector<float> expected = model_->XgboostMargins(states.data(), rows);
  const FlatTreeEnsemble& trees = model_->trees();
  for (const TreeKernel kernel :
       {TreeKernel::kFastest, TreeKernel::kAvx2, TreeKernel::kBitvectors, TreeKernel::kRowByRow}) {
    for (const int threads : {1, 2, 0}) {
      std::vector<float> margins(rows);
      trees.Margins(states.data(), rows, margins.data(), threads, kernel);
      EXPECT_EQ(margins, expected)
          << "kernel " << static_cast<int>(kernel) << ", threads " << threads;
    }
  }
  // One row alone (a block of 1) too.
  float one = 0.0f;
  trees.Margins(states.data() + 7 * kHazardStateDim, 1, &one);
  EXPECT_EQ(one, expected[7]);
}

TEST(XgbCostModelLargeTreesTest, TreesOfMoreThan32LeavesFallBackAndStillMatchXgboost) {
  const testing::HazardData data = testing::MakeHazardData(6000, 2000, 4);
  XgbCostModelOptions options;
  options.rounds = 20;
  options.max_leaves = 48;
  options.max_depth = 12;
  XgbCostModel model(kHazardStateDim, options, 5);
  model.FitArrays(data.safe.data(), data.safe_count, data.unsafe.data(), data.unsafe_count);
  const std::vector<std::int32_t>& roots = model.trees().roots();
  int first_tree_leaves = 0;
  for (std::int32_t node = roots[0]; node < roots[1]; ++node) {
    first_tree_leaves += model.trees().nodes()[node].is_leaf();
  }
  ASSERT_GT(first_tree_leaves, 32) << "the test needs a tree too large for the bitvectors";
  const int rows = 1000;
  const std::vector<float> states = RowsWithMissingValues(data.safe, rows);
  EXPECT_EQ(model.Margins(states.data(), rows), model.XgboostMargins(states.data(), rows));
}

// The row walk (RowMargin: FlatTreeEnsemble's reference and the CUDA kernel's arithmetic,
// compiled for the host here) on the nodes as the kernel receives them gives XGBoost's margins
// bit for bit, missing values included: checked on any machine, the launch only on a GPU (below).
TEST_F(XgbCostModelTest, TheRowWalkGivesXgboostsBits) {
  const int rows = 2001;
  const std::vector<float> states = RowsWithMissingValues(test_->safe, rows);
  const std::vector<float> expected = model_->XgboostMargins(states.data(), rows);
  const FlatTreeEnsemble& trees = model_->trees();
  for (int r = 0; r < rows; ++r) {
    const float* row = states.data() + r * kHazardStateDim;
    const float margin = RowMargin(trees.nodes().data(), trees.roots().data(), trees.num_trees(),
                                   trees.base_margin(), row);
    ASSERT_EQ(margin, expected[r]) << "row " << r;
    ASSERT_EQ(trees.Margin(row), margin) << "row " << r;
  }
}

TEST_F(XgbCostModelTest, TensorTreesNameStatesTheyCannotClassify) {
  const TreeEnsembleTensors tensors(model_->trees(), torch::Device(torch::kCPU));
  EXPECT_FALSE(tensors.uses_cuda_kernel());
  const auto error = [&](const torch::Tensor& states) {
    return ErrorMessage([&] { tensors.Margins(states); });
  };
  EXPECT_THAT(
      error(torch::zeros({4, 3})),
      ::testing::HasSubstr("states of shape [4, 3]: expected (rows, columns) with at least"));
  EXPECT_THAT(error(torch::zeros({4, kHazardStateDim}, torch::kDouble)),
              ::testing::HasSubstr("states must be float32 on cpu"));
}

// Missing values and infinities too: the tensor path sends NaN the default way by widening the
// row (NaN as -inf, then as +inf), which must not move an infinite value.
TEST_F(XgbCostModelTest, TensorTreesAgreeWithTheFlatTrees) {
  const int rows = 3000;
  std::vector<float> values = RowsWithMissingValues(test_->safe, rows);
  for (int i = 3; i < rows; i += 11) values[i * kHazardStateDim + 5] = INFINITY;
  for (int i = 5; i < rows; i += 13) values[i * kHazardStateDim + 2] = -INFINITY;
  const std::vector<float> flat = model_->Margins(values.data(), rows);  // XGBoost refuses inf
  const torch::Tensor states = torch::from_blob(values.data(), {rows, kHazardStateDim}).clone();
  const TreeEnsembleTensors tensors(model_->trees(), torch::Device(torch::kCPU));
  const torch::Tensor margins = tensors.Margins(states);
  const torch::Tensor expected = torch::tensor(flat);
  // Summation order differs: margins of magnitude up to ~30 agree to 1e-4.
  EXPECT_LT((margins - expected).abs().max().item<float>(), 1e-4f);
  // And the class agrees on every row whose margin is not within that of the threshold.
  const torch::Tensor clear = expected.abs() > 1e-4f;
  EXPECT_TRUE(
      torch::equal((margins > 0).masked_select(clear), (expected > 0).masked_select(clear)));
  // PredictViolation keeps batch shapes: (2, 1500, S) -> (2, 1500).
  const torch::Tensor clean = torch::from_blob(test_->safe.data(), {2, rows / 2, kHazardStateDim});
  const torch::Tensor violations = model_->PredictViolation(clean);
  ASSERT_EQ(violations.sizes(), torch::IntArrayRef({2, rows / 2}));
  const std::vector<std::uint8_t> rows_result = model_->PredictRows(test_->safe.data(), rows);
  for (int i = 0; i < rows; ++i) {
    ASSERT_EQ(violations.reshape({-1})[i].item<float>(), rows_result[i]) << "row " << i;
  }
}

// The launches a GPU pays for: six operations per tree level (the column, the value, the
// threshold, the comparison, the first child, the step), counted as LibTorch's top-level calls;
// the first form took ten. Views and the per-chunk set-up add a few more.
TEST_F(XgbCostModelTest, TensorTreesTakeSixOperationsATreeLevel) {
  const int rows = 500;
  const torch::Tensor states =
      torch::from_blob(test_->safe.data(), {rows, kHazardStateDim}).clone();
  const TreeEnsembleTensors tensors(model_->trees(), torch::Device(torch::kCPU));
  ASSERT_EQ(tensors.chunk_rows() >= rows, true);
  static thread_local int depth = 0;
  static thread_local int calls = 0;
  calls = 0;
  const at::CallbackHandle handle = at::addThreadLocalCallback(
      at::RecordFunctionCallback(
          [](const at::RecordFunction&) -> std::unique_ptr<at::ObserverContext> {
            if (depth++ == 0) ++calls;
            return nullptr;
          },
          [](const at::RecordFunction&, at::ObserverContext*) { --depth; })
          .scopes({at::RecordScope::FUNCTION}));
  tensors.Margins(states);
  at::removeCallback(handle);
  const int levels = model_->trees().max_depth();
  ASSERT_GE(levels, 4);
  // Measured: 63 at depth 8 (48 in the levels); the ten-operation form made 90.
  EXPECT_GE(calls, 6 * levels);
  EXPECT_LE(calls, 6 * levels + 16);
}

// A row's margin is the same whatever the chunk it is classified in: a GPU's large chunks (few
// launches) give a CPU's small chunks' margins, bit for bit.
TEST_F(XgbCostModelTest, TensorTreesGiveTheSameMarginsInAnyChunking) {
  const int rows = 3000;
  const torch::Tensor states =
      torch::from_blob(test_->safe.data(), {rows, kHazardStateDim}).clone();
  const std::int64_t trees = static_cast<std::int64_t>(model_->trees().roots().size());
  const torch::Device cpu(torch::kCPU);
  const TreeEnsembleTensors whole(model_->trees(), cpu, trees * rows);
  ASSERT_EQ(whole.chunk_rows(), rows);
  const torch::Tensor expected = whole.Margins(states);
  for (const std::int64_t chunk_rows : {1, 7, 1024}) {
    const TreeEnsembleTensors chunked(model_->trees(), cpu, trees * chunk_rows);
    ASSERT_EQ(chunked.chunk_rows(), chunk_rows);
    EXPECT_TRUE(torch::equal(chunked.Margins(states), expected)) << chunk_rows << " rows a chunk";
  }
  EXPECT_EQ(TreeEnsembleTensors(model_->trees(), cpu).chunk_rows(), (1 << 21) / trees);
  EXPECT_THROW(TreeEnsembleTensors(model_->trees(), cpu, -1), Error);
}

// On a GPU: the kernel (where built) gives XGBoost's bits, missing values included; the tensor
// operations agree with the CPU's to the last bits of their sum.
TEST_F(XgbCostModelTest, TensorTreesOnCudaAgreeWhenAvailable) {
  if (!torch::cuda::is_available()) GTEST_SKIP() << "this LibTorch has no CUDA or sees no GPU";
  const int rows = 3001;
  std::vector<float> missing = RowsWithMissingValues(test_->safe, rows);
  const torch::Tensor states = torch::from_blob(missing.data(), {rows, kHazardStateDim}).clone();
  const torch::Tensor expected = torch::tensor(model_->XgboostMargins(missing.data(), rows));
  const torch::Device gpu(torch::kCUDA);
  const TreeEnsembleTensors fastest(model_->trees(), gpu);
  EXPECT_EQ(fastest.uses_cuda_kernel(), TreeEnsembleTensors::CudaKernelBuilt());
  if (fastest.uses_cuda_kernel()) {
    EXPECT_TRUE(torch::equal(fastest.Margins(states.cuda()).cpu(), expected));
  }
  const TreeEnsembleTensors ops(model_->trees(), gpu, 0, DeviceTreePath::kTensorOps);
  EXPECT_FALSE(ops.uses_cuda_kernel());
  EXPECT_LT((ops.Margins(states.cuda()).cpu() - expected).abs().max().item<float>(), 1e-4f);
}

// XGBoost's fit builds the same trees on any thread count: a run's classifier does not depend
// on the cores it is given (the shared model fits with the default, one thread per core).
TEST_F(XgbCostModelTest, AFitOnAnyThreadCountGivesTheSameTrees) {
  for (const int threads : {1, 2, 4}) {
    XgbCostModelOptions options;
    options.threads = threads;
    XgbCostModel threaded(kHazardStateDim, options, 3);
    threaded.Fit(*buffer_);
    EXPECT_EQ(threaded.Margins(test_->unsafe.data(), 2000),
              model_->Margins(test_->unsafe.data(), 2000))
        << threads << " threads";
    EXPECT_EQ(threaded.Margins(test_->safe.data(), 10000),
              model_->Margins(test_->safe.data(), 10000))
        << threads << " threads";
  }
}

TEST_F(XgbCostModelTest, SaveThenLoadPredictsTheSame) {
  const std::string path = testing::TestTempPath("cost_model_test.json");
  model_->Save(path);
  XgbCostModel loaded(kHazardStateDim, XgbCostModelOptions{}, 99);
  loaded.Load(path);
  EXPECT_TRUE(loaded.trained());
  EXPECT_EQ(loaded.Margins(test_->unsafe.data(), 500), model_->Margins(test_->unsafe.data(), 500));
  XgbCostModel wrong(10, XgbCostModelOptions{}, 1);
  EXPECT_THAT(ErrorMessage([&] { wrong.Load(path); }),
              ::testing::HasSubstr("is for 24 state dimensions, this model has 10"));
  std::filesystem::remove(path);
}

// A fit abandoned after its third round leaves the model as the last whole fit made it.
TEST_F(XgbCostModelTest, AnInterruptedFitLeavesTheModelAsItWas) {
  const std::string path = testing::TestTempPath("before.json");
  model_->Save(path);
  XgbCostModel model(kHazardStateDim, XgbCostModelOptions{}, 3);
  model.Load(path);
  const std::vector<float> before = model.Margins(test_->unsafe.data(), 500);
  int rounds = 0;
  const std::vector<float> flipped_safe(test_->unsafe.begin(),
                                        test_->unsafe.begin() + 100 * kHazardStateDim);
  const std::vector<float> flipped_unsafe(test_->safe.begin(),
                                          test_->safe.begin() + 300 * kHazardStateDim);
  const CostFitReport report = model.FitArrays(flipped_safe.data(), 100, flipped_unsafe.data(), 300,
                                               [&] { return ++rounds < 3; });
  EXPECT_TRUE(report.interrupted);
  EXPECT_EQ(rounds, 3);
  EXPECT_EQ(model.Margins(test_->unsafe.data(), 500), before);
  // Without interruption the same fit changes the model.
  EXPECT_FALSE(model.FitArrays(flipped_safe.data(), 100, flipped_unsafe.data(), 300).interrupted);
  EXPECT_NE(model.Margins(test_->unsafe.data(), 500), before);
}

TEST(XgbCostModelEdgeTest, WithoutUnsafeStatesEverythingIsSafe) {
  LabeledStateBuffer buffer(3);
  buffer.Add({0, 0, 0}, false);
  XgbCostModel model(3, XgbCostModelOptions{}, 1);
  const CostFitReport report = model.Fit(buffer);
  EXPECT_FALSE(report.trained);
  EXPECT_EQ(report.unsafe_used, 0);
  EXPECT_TRUE(std::isnan(report.unsafe_accuracy));
  const float rows[] = {0, 0, 0, 5, 5, 5};
  EXPECT_EQ(model.PredictRows(rows, 2), std::vector<std::uint8_t>({0, 0}));
  EXPECT_TRUE(torch::equal(model.PredictViolation(torch::ones({4, 3})), torch::zeros({4})));
}

TEST(XgbCostModelEdgeTest, OnlyUnsafeStatesPredictUnsafe) {
  LabeledStateBuffer buffer(1);
  buffer.Add({1}, true);
  buffer.Add({2}, true);
  XgbCostModelOptions options;
  options.safe_per_unsafe = 0;
  options.rounds = 5;
  XgbCostModel model(1, options, 1);
  const CostFitReport report = model.Fit(buffer);
  EXPECT_EQ(report.safe_used, 0);  // the buffer holds no safe state
  const float rows[] = {1.5f};
  EXPECT_EQ(model.PredictRows(rows, 1), std::vector<std::uint8_t>({1}));
}

TEST(XgbCostModelEdgeTest, BadInputsAreRefusedByName) {
  XgbCostModel model(2, XgbCostModelOptions{}, 1);
  const float rows[] = {0.0f, std::numeric_limits<float>::quiet_NaN()};
  EXPECT_EQ(ErrorMessage([&] { model.PredictRows(rows, 1); }),
            "state 0 has a non-finite value nan in column 1: expected finite numbers");
  EXPECT_EQ(ErrorMessage([&] {
              model.PredictViolation(torch::zeros({5, 3}));
            }),
            "states has shape [5, 3]: expected (..., 2)");
  XgbCostModelOptions options;
  options.max_leaves = 1;
  EXPECT_EQ(ErrorMessage([&] { XgbCostModel(2, options, 1); }),
            "max_leaves is 1: expected 2 to 1000000");
  options = XgbCostModelOptions{};
  options.threshold = 1.0;
  EXPECT_THAT(ErrorMessage([&] { XgbCostModel(2, options, 1); }),
              ::testing::HasSubstr("threshold is 1"));
}

// A hand-written model of one tree: x[1] < 0.5 (NaN left) -> 0.25, else x[0] < -1 (NaN right)
// -> -0.5 or 1.0; base_score 0.5 gives base margin 0.
std::string OneTreeJson(const std::string& left, const std::string& right,
                        const std::string& features,
                        const std::string& values = "[0.5, 0.25, -1.0, -0.5, 1.0]",
                        const std::string& default_left = "[1, 0, 0, 0, 0]") {
  return R"({"learner": {"objective": {"name": "binary:logistic"},
    "learner_model_param": {"num_feature": "2", "base_score": "5E-1"},
    "gradient_booster": {"name": "gbtree", "model": {"trees": [{
      "left_children": )" +
         left + R"(, "right_children": )" + right + R"(, "split_indices": )" + features +
         R"(, "split_conditions": )" + values + R"(, "default_left": )" + default_left +
         R"(}]}}}})";
}

TEST(FlatTreeEnsembleTest, AHandWrittenTreeIsWalkedAsWritten) {
  const FlatTreeEnsemble trees = FlatTreeEnsemble::FromXgboostJson(
      OneTreeJson("[1, -1, 3, -1, -1]", "[2, -1, 4, -1, -1]", "[1, 0, 0, 0, 0]"));
  ASSERT_EQ(trees.num_trees(), 1);
  EXPECT_EQ(trees.max_depth(), 2);
  EXPECT_EQ(trees.base_margin(), 0.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<std::pair<std::vector<float>, float>> cases = {{{5.0f, 0.0f}, 0.25f},
                                                                   {{5.0f, nan}, 0.25f},
                                                                   {{-2.0f, 1.0f}, -0.5f},
                                                                   {{0.0f, 1.0f}, 1.0f},
                                                                   {{nan, 1.0f}, 1.0f}};
  for (const auto& [row, margin] : cases) {
    EXPECT_EQ(trees.Margin(row.data()), margin) << row[0] << ", " << row[1];
    float out = 0.0f;
    trees.Margins(row.data(), 1, &out);
    EXPECT_EQ(out, margin) << row[0] << ", " << row[1];
  }
  const std::vector<TreeNode>& nodes = trees.nodes();
  EXPECT_TRUE(nodes[1].is_leaf());
  EXPECT_EQ(nodes[1].left, 1);  // a leaf points at itself
  EXPECT_EQ(nodes[0].feature(), 1);
  EXPECT_TRUE(nodes[0].default_left());
  EXPECT_FALSE(nodes[2].default_left());
}

TEST(FlatTreeEnsembleTest, BadTreesAreRefusedByName) {
  struct BadTree {
    const char* left;
    const char* right;
    const char* features;
    const char* error;
  };
  const std::vector<BadTree> cases = {
      {"[1, -1, 3, -1, -1]", "[2, -1, 7, -1, -1]", "[1, 0, 0, 0, 0]",
       "XGBoost node 2 of tree 0 has children 3 and 7: expected 0 to 4"},
      {"[1, -1, 3, -1, -1]", "[2, -1, 4, -1, -1]", "[1, 0, 2, 0, 0]",
       "XGBoost split on feature 2 of 2"},
      {"[1, -1, 3, -1]", "[2, -1, 4, -1, -1]", "[1, 0, 0, 0, 0]",
       "XGBoost tree arrays differ in length"},
      // In range, but not a tree: node 2's left child is the root (a cycle), or node 1 (two
      // parents).
      {"[1, -1, 0, -1, -1]", "[2, -1, 4, -1, -1]", "[1, 0, 0, 0, 0]",
       "XGBoost tree 0 reaches its node 0 twice: expected a tree"},
      {"[1, -1, 1, -1, -1]", "[2, -1, 4, -1, -1]", "[1, 0, 0, 0, 0]",
       "XGBoost tree 0 reaches its node 1 twice: expected a tree"},
  };
  for (const BadTree& tree : cases) {
    EXPECT_EQ(
        ErrorMessage([&] {
          FlatTreeEnsemble::FromXgboostJson(OneTreeJson(tree.left, tree.right, tree.features));
        }),
        tree.error)
        << tree.left << " " << tree.right << " " << tree.features;
  }
  EXPECT_EQ(ErrorMessage([] {
              FlatTreeEnsemble::FromXgboostJson(OneTreeJson("[]", "[]", "[]", "[]", "[]"));
            }),
            "XGBoost tree 0 has no nodes");
}

}  // namespace
}  // namespace cmbrl
