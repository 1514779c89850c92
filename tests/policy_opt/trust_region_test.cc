#include "cmbrl/policy_opt/trust_region.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/error_message.h"

namespace cmbrl {
namespace {

TEST(ConjugateGradientTest, SolvesAFixedSymmetricPositiveDefiniteSystem) {
  const torch::Tensor a = torch::tensor({4.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 2.0},
                                        torch::kDouble)
                              .view({3, 3});
  const torch::Tensor b = torch::tensor({1.0, 2.0, 3.0}, torch::kDouble);
  int products = 0;
  const torch::Tensor x = ConjugateGradient(
      [&](const torch::Tensor& v) {
        ++products;
        return torch::mv(a, v);
      },
      b, 10);
  // Three directions solve a 3 x 3 system; the original's 1e-8 added to each step's denominator
  // leaves a residual of order 1e-8 (measured 8.7e-9), and the later steps stay finite.
  EXPECT_LT((torch::mv(a, x) - b).abs().max().item<double>(), 1e-7);
  EXPECT_TRUE(torch::isfinite(x).all().item<bool>());
  EXPECT_GE(products, 3);
  // One iteration is the steepest-descent step along b: alpha b with alpha = b.b / b.Ab.
  const torch::Tensor one = ConjugateGradient([&](const torch::Tensor& v) { return torch::mv(a, v); },
                                              b, 1);
  const double alpha = b.dot(b).item<double>() / b.dot(torch::mv(a, b)).item<double>();
  EXPECT_LT((one - alpha * b).abs().max().item<double>(), 1e-8);  // the same 1e-8 in alpha
}

// The hand-solved instances below: q, r, s, c and target 0.01 chosen so that each case's
// multipliers come out in closed form. Where the step is not a recovery, a KL of 0.5 x^T H x =
// 0.01 and an active cost constraint c - b^T x = 0 are checked from q, r, s.
constexpr double kTrustRegionTol = 1e-6;

double StepKl(const CpoDualSolution& d, const CpoDualInputs& in) {
  const double cv = d.v_coefficient, cw = d.w_coefficient;
  return 0.5 * (cv * cv * in.q + 2 * cv * cw * in.r + cw * cw * in.s);
}

double CostAfterStep(const CpoDualSolution& d, const CpoDualInputs& in) {
  return in.c - (d.v_coefficient * in.r + d.w_coefficient * in.s);  // c + b^T (theta' - theta)
}

TEST(CpoDualTest, Case4IsThePlainTrpoStep) {
  const CpoDualInputs in{2.0, 0.0, 0.0, -1.0, 0.01, /*cost_gradient_vanishes=*/true};
  const CpoDualSolution d = SolveCpoDual(in);
  EXPECT_EQ(d.optim_case, 4);
  EXPECT_NEAR(d.lambda, 10.0, kTrustRegionTol);  // sqrt(q / (2 delta))
  EXPECT_NEAR(d.v_coefficient, 0.1, kTrustRegionTol);
  EXPECT_EQ(d.w_coefficient, 0.0);
  EXPECT_NEAR(d.v_coefficient, NaturalStepScale(in.q, in.target_kl), kTrustRegionTol);
}

TEST(CpoDualTest, Case3TheWholeTrustRegionIsFeasible) {
  // B = 0.02 - 1 / 1 < 0 with c < 0.
  const CpoDualSolution d = SolveCpoDual({2.0, 1.0, 1.0, -1.0, 0.01, false});
  EXPECT_EQ(d.optim_case, 3);
  EXPECT_NEAR(d.lambda, 10.0, kTrustRegionTol);
  EXPECT_EQ(d.nu, 0.0);
  EXPECT_NEAR(d.b, -0.98, kTrustRegionTol);
}

TEST(CpoDualTest, Case2TheConstraintCutsTheRegionAndIsActive) {
  // A = 2 - 1 = 1, B = 0.02 - 0.0025 = 0.0175, r / c = 20: lambda_a = sqrt(A / B) = 7.559289
  // beats lambda_b = 20 (dual -0.1823 against -0.25); nu = (lambda c - r) / s = 0.6220355.
  const CpoDualInputs in{2.0, -1.0, 1.0, -0.05, 0.01, false};
  const CpoDualSolution d = SolveCpoDual(in);
  EXPECT_EQ(d.optim_case, 2);
  EXPECT_NEAR(d.a, 1.0, kTrustRegionTol);
  EXPECT_NEAR(d.b, 0.0175, kTrustRegionTol);
  EXPECT_NEAR(d.lambda, std::sqrt(1.0 / 0.0175), kTrustRegionTol);
  EXPECT_NEAR(d.nu, 1.0 - 0.05 * std::sqrt(1.0 / 0.0175), kTrustRegionTol);
  EXPECT_NEAR(StepKl(d, in), 0.01, kTrustRegionTol);
  EXPECT_NEAR(CostAfterStep(d, in), 0.0, kTrustRegionTol);
}

TEST(CpoDualTest, Case1RecoversFromAnInfeasiblePolicy) {
  // c > 0 now: the intervals swap, lambda_b projects to 0 (dual -1e8), lambda = 7.559289 and
  // nu = (lambda c - r) / s = 1.3779645; the step lands on the constraint's boundary.
  const CpoDualInputs in{2.0, -1.0, 1.0, 0.05, 0.01, false};
  const CpoDualSolution d = SolveCpoDual(in);
  EXPECT_EQ(d.optim_case, 1);
  EXPECT_NEAR(d.lambda, std::sqrt(1.0 / 0.0175), kTrustRegionTol);
  EXPECT_NEAR(d.nu, 1.0 + 0.05 * std::sqrt(1.0 / 0.0175), kTrustRegionTol);
  EXPECT_NEAR(StepKl(d, in), 0.01, kTrustRegionTol);
  EXPECT_NEAR(CostAfterStep(d, in), 0.0, kTrustRegionTol);
}

TEST(CpoDualTest, Case0StepsOnlyToLowerTheCost) {
  // B = 0.02 - 0.25 < 0 with c > 0: no feasible point in the region. x = nu w, nu = sqrt(2 delta
  // / s): the largest pure cost-descent step within the KL target.
  const CpoDualInputs in{2.0, -1.0, 1.0, 0.5, 0.01, false};
  const CpoDualSolution d = SolveCpoDual(in);
  EXPECT_EQ(d.optim_case, 0);
  EXPECT_EQ(d.v_coefficient, 0.0);
  EXPECT_NEAR(d.w_coefficient, std::sqrt(0.02), kTrustRegionTol);
  EXPECT_NEAR(StepKl(d, in), 0.01, kTrustRegionTol);
  EXPECT_LT(CostAfterStep(d, in), in.c);  // lower, though not yet feasible
}

TEST(CpoDualTest, BadInputsAreNamed) {
  EXPECT_THAT(testing::ErrorMessage([] { SolveCpoDual({1, 0, 1, 0, 0.0, false}); }),
              ::testing::HasSubstr("target_kl is 0"));
  EXPECT_THAT(testing::ErrorMessage([] { SolveCpoDual({NAN, 0, 1, 0, 0.01, false}); }),
              ::testing::HasSubstr("must be finite"));
}

}  // namespace
}  // namespace cmbrl
