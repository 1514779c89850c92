#include "cmbrl/planning/reward_term.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <torch/torch.h>

#include "cmbrl/core/check.h"
#include "cmbrl/core/closest_name.h"

namespace cmbrl {

GoalDistanceTerm::GoalDistanceTerm(TrajectoryObjectiveOptions options)
    : options_(std::move(options)) {}

void GoalDistanceTerm::CheckStateSize(int state_dim) const {
  RequireGoalIndexFits(options_, state_dim);
}

torch::Tensor GoalDistanceTerm::Cost(const torch::Tensor&, const torch::Tensor&,
                                     const torch::Tensor& next_states) const {
  const torch::Tensor goal = next_states.narrow(-1, options_.goal_index, 2);
  const torch::Tensor distance = goal.norm(2, -1);
  const torch::Tensor near =
      distance - options_.near_goal_bonus * (distance < options_.near_goal_radius);
  const torch::Tensor tested = options_.at_goal_test_after_near_bonus ? near : distance;
  return near - options_.at_goal_bonus * (tested < options_.at_goal_radius);
}

ObservationRewardTerm::ObservationRewardTerm(std::string form, int offset, int width,
                                             std::vector<double> target, int axis)
    : form_(std::move(form)),
      offset_(offset),
      width_(width),
      target_(std::move(target)),
      axis_(axis) {
  Require(form_ == "site-distance" || form_ == "speed-along" || form_ == "height",
          "unknown observation reward '{}'", form_);
  Require(form_ != "site-distance" || static_cast<int>(target_.size()) == width_,
          "the site-distance target has {} values for a sensor of {}", target_.size(), width_);
  Require(form_ == "site-distance" || (axis_ >= 0 && axis_ < width_),
          "reward axis {} is outside the sensor's {} values", axis_, width_);
}

void ObservationRewardTerm::CheckStateSize(int state_dim) const {
  Require(offset_ >= 0 && offset_ + width_ <= state_dim,
          "the reward reads state components {} to {}: the state has {}", offset_,
          offset_ + width_ - 1, state_dim);
}

torch::Tensor ObservationRewardTerm::Cost(const torch::Tensor&, const torch::Tensor&,
                                          const torch::Tensor& next_states) const {
  const torch::Tensor values = next_states.narrow(-1, offset_, width_);
  if (form_ == "site-distance") {
    const torch::Tensor target =
        torch::tensor(target_, torch::kDouble).to(values.device(), values.scalar_type());
    return (values - target).norm(2, -1);  // a cost: the distance itself
  }
  const torch::Tensor component = values.select(-1, axis_);
  if (form_ == "speed-along") return -component;
  return (component - target_[0]).abs();  // height
}

namespace {

// A lone object's ego distance and angle from its lidar block (..., bins) of state.
struct LidarReading {
  torch::Tensor distance, cos, sin;
};

LidarReading ReadLidar(const torch::Tensor& states, const LidarBlock& block) {
  const torch::Tensor bins = states.narrow(-1, block.offset, block.bins);
  const auto [largest, bin] = bins.max(-1);
  const torch::Tensor reading = largest.clamp(0.0, 1.0);
  const torch::Tensor next = bins.gather(-1, ((bin + 1) % block.bins).unsqueeze(-1)).squeeze(-1);
  const torch::Tensor alias = (next / reading.clamp_min(1e-6)).clamp(0.0, 1.0);
  const torch::Tensor angle = (bin.to(states.scalar_type()) + alias) * (2.0 * M_PI / block.bins);
  return {block.max_dist * (1.0 - reading), angle.cos(), angle.sin()};
}

}  // namespace

LidarRewardTerm::LidarRewardTerm(std::string form, std::vector<LidarBlock> blocks, int velocimeter,
                                 TrajectoryObjectiveOptions options, double circle_radius)
    : form_(std::move(form)),
      blocks_(std::move(blocks)),
      velocimeter_(velocimeter),
      options_(std::move(options)),
      circle_radius_(circle_radius) {
  const size_t needed = form_ == kPushLidarDistancesReward ? 2 : 1;
  Require(form_ == kGoalLidarDistanceReward || form_ == kPushLidarDistancesReward ||
              form_ == kCircleLidarSpeedReward,
          "unknown lidar reward '{}'", form_);
  Require(blocks_.size() == needed, "the {} reward reads {} lidar block(s), got {}", form_, needed,
          blocks_.size());
}

void LidarRewardTerm::CheckStateSize(int state_dim) const {
  for (const LidarBlock& block : blocks_) {
    Require(block.offset >= 0 && block.offset + block.bins <= state_dim,
            "the {} reward reads state components {} to {}: the state has {}", form_,
            block.offset, block.offset + block.bins - 1, state_dim);
  }
  Require(form_ != kCircleLidarSpeedReward || (velocimeter_ >= 0 && velocimeter_ + 2 <= state_dim),
          "the {} reward reads the velocimeter at state components {} and {}: the state has {}",
          form_, velocimeter_, velocimeter_ + 1, state_dim);
}

torch::Tensor LidarRewardTerm::Cost(const torch::Tensor&, const torch::Tensor&,
                                    const torch::Tensor& next_states) const {
  if (form_ == kGoalLidarDistanceReward) {
    const torch::Tensor distance = ReadLidar(next_states, blocks_[0]).distance;
    const torch::Tensor near =
        distance - options_.near_goal_bonus * (distance < options_.near_goal_radius);
    const torch::Tensor tested = options_.at_goal_test_after_near_bonus ? near : distance;
    return near - options_.at_goal_bonus * (tested < options_.at_goal_radius);
  }
  if (form_ == kPushLidarDistancesReward) {
    const LidarReading box = ReadLidar(next_states, blocks_[0]);
    const LidarReading goal = ReadLidar(next_states, blocks_[1]);
    const torch::Tensor dx = goal.distance * goal.cos - box.distance * box.cos;
    const torch::Tensor dy = goal.distance * goal.sin - box.distance * box.sin;
    return box.distance + (dx * dx + dy * dy).sqrt();
  }
  // circle-lidar-speed: the robot sits at -r (cos, sin) from the centre in its own frame, so the
  // world's (-u y + v x) / r is sin u_ego - cos v_ego.
  const LidarReading centre = ReadLidar(next_states, blocks_[0]);
  const torch::Tensor u = next_states.select(-1, velocimeter_);
  const torch::Tensor v = next_states.select(-1, velocimeter_ + 1);
  const torch::Tensor around = centre.sin * u - centre.cos * v;
  return -0.1 * around / (1.0 + (centre.distance - circle_radius_).abs());
}

std::unique_ptr<RewardTerm> MakeAnalyticReward(const std::string& form,
                                               const TrajectoryObjectiveOptions& options,
                                               const std::vector<std::string>& observation_names,
                                               const LidarGeometry& geometry) {
  if (form == kGoalDistanceReward) return std::make_unique<GoalDistanceTerm>(options);
  Require(geometry.max_dist > 0.0 && std::isfinite(geometry.max_dist),
          "the analytic reward '{}' reads lidars whose range is {} m: expected the task's range, "
          "a positive number of metres",
          form, geometry.max_dist);
  const auto index_of = [&](const std::string& name) {
    const auto found = std::find(observation_names.begin(), observation_names.end(), name);
    Require(found != observation_names.end(),
            "the analytic reward '{}' reads the observation's '{}', which it lacks: the lidar "
            "forms plan on a stock task's lidar observation (variant standard)",
            form, name);
    return static_cast<int>(found - observation_names.begin());
  };
  const auto block = [&](const std::string& key) {
    LidarBlock lidar;
    lidar.offset = index_of(key + "_0");
    lidar.bins = 0;
    while (lidar.offset + lidar.bins < static_cast<int>(observation_names.size()) &&
           observation_names[lidar.offset + lidar.bins] == fmt::format("{}_{}", key, lidar.bins)) {
      ++lidar.bins;
    }
    lidar.max_dist = geometry.max_dist;
    return lidar;
  };
  if (form == kGoalLidarDistanceReward) {
    return std::make_unique<LidarRewardTerm>(form, std::vector{block("goal_lidar")}, -1, options,
                                             geometry.circle_radius);
  }
  if (form == kPushLidarDistancesReward) {
    return std::make_unique<LidarRewardTerm>(
        form, std::vector{block("push_box_lidar"), block("goal_lidar")}, -1, options,
        geometry.circle_radius);
  }
  if (form == kCircleLidarSpeedReward) {
    Require(geometry.circle_radius > 0.0 && std::isfinite(geometry.circle_radius),
            "the analytic reward '{}' needs the circle's radius: got {} m, expected the task's",
            form, geometry.circle_radius);
    return std::make_unique<LidarRewardTerm>(form, std::vector{block("circle_lidar")},
                                             index_of("velocimeter_x"), options,
                                             geometry.circle_radius);
  }
  Fail("unknown analytic reward '{}'{}: expected one of {}", form,
       DidYouMean(form, AnalyticRewardNames()), fmt::join(AnalyticRewardNames(), ", "));
}

}  // namespace cmbrl
