// Analytic objectives for planner tests.
#pragma once

#include <torch/torch.h>

#include <algorithm>
#include <vector>

#include "cmbrl/planning/planner.h"

namespace cmbrl::testing {

// A point moved by 0.3 * action per step from the origin towards a goal at (2.4, 0); the
// corridor |y| <= half_width is safe, everything outside violates.
class CorridorObjective : public Objective {
 public:
  explicit CorridorObjective(double half_width) : half_width_(half_width) {}
  ObjectiveValues Evaluate(const torch::Tensor& actions) override {
    const torch::Tensor positions = (0.3 * actions).cumsum(1);  // (N, H, 2)
    const int64_t h = actions.size(1);
    const torch::Tensor discount = torch::pow(0.98, torch::arange(h, actions.options()));
    const torch::Tensor goal = torch::tensor({2.4f, 0.0f}, actions.options());
    const torch::Tensor distance = (positions - goal).norm(2, -1);
    const torch::Tensor unsafe = (positions.select(2, 1).abs() > half_width_).to(torch::kFloat);
    return {(discount * distance).sum(1), (discount * unsafe).sum(1)};
  }
  // The constraint cost of one sequence (H, 2).
  float ConstraintOf(const torch::Tensor& sequence) {
    return Evaluate(sequence.unsqueeze(0)).constraint_cost.item<float>();
  }

 private:
  double half_width_;
};

// Sum of squared distances of every action to `target` (a known optimum inside or outside the
// box); never infeasible. Records the range of the actions it was asked to score.
class QuadraticObjective : public Objective {
 public:
  explicit QuadraticObjective(std::vector<float> target) : target_(std::move(target)) {}
  ObjectiveValues Evaluate(const torch::Tensor& actions) override {
    lowest_ = std::min(lowest_, actions.min().item<float>());
    highest_ = std::max(highest_, actions.max().item<float>());
    const torch::Tensor target =
        torch::tensor(target_, actions.options()).view({actions.size(1), actions.size(2)});
    const torch::Tensor cost = (actions - target).pow(2).sum({1, 2});
    return {cost, torch::zeros_like(cost)};
  }
  float lowest() const { return lowest_; }
  float highest() const { return highest_; }

 private:
  std::vector<float> target_;
  float lowest_ = 1e9f, highest_ = -1e9f;
};

// The optimum of a QuadraticObjective of horizon 8 and two action dimensions where every step
// wants (x, y), flattened (H * A) and as a tensor (H, A).
inline std::vector<float> RepeatedTarget(float x, float y) {
  std::vector<float> target;
  for (int t = 0; t < 8; ++t) {
    target.push_back(x);
    target.push_back(y);
  }
  return target;
}
inline torch::Tensor RepeatedTargetTensor(float x, float y) {
  return torch::tensor(RepeatedTarget(x, y)).view({8, 2});
}

}  // namespace cmbrl::testing
