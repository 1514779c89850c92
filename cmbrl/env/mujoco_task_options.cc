#include "cmbrl/env/mujoco_task_options.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "cmbrl/core/check.h"
#include "cmbrl/core/closest_name.h"

namespace cmbrl {

LidarGroup ParseLidarGroup(const std::string& entry) {
  const size_t colon = entry.find(':');
  Require(colon != std::string::npos && colon > 0 && colon + 1 < entry.size(),
          "lidar_groups holds '{}': expected 'name:body1,body2'", entry);
  LidarGroup group;
  group.name = entry.substr(0, colon);
  std::string bodies = entry.substr(colon + 1);
  for (size_t start = 0; start <= bodies.size();) {
    const size_t comma = std::min(bodies.find(',', start), bodies.size());
    const std::string body = bodies.substr(start, comma - start);
    Require(!body.empty(), "lidar_groups holds '{}': a body name is empty", entry);
    group.bodies.push_back(body);
    start = comma + 1;
  }
  return group;
}

std::vector<std::string> ObservationRewardForms() {
  return {"site-distance", "speed-along", "height"};
}

void ValidateMujocoTaskOptions(const MujocoTaskOptions& o) {
  if (!IsDeclaredTask(o)) return;
  Require(!o.sensors.empty(), "sensors is empty: expected the MuJoCo sensors the agent observes");
  Require(o.lidar_groups.empty() || !o.lidar_body.empty(),
          "lidar_groups is set but lidar_body is empty: expected the body the lidar sees from");
  for (const std::string& entry : o.lidar_groups) ParseLidarGroup(entry);
  Require(o.lidar_bins >= 1 && o.lidar_bins <= 1024, "lidar_bins is {}: expected 1 to 1024",
          o.lidar_bins);
  Require(o.lidar_max_dist > 0 && o.lidar_max_dist <= 1e6,
          "lidar_max_dist is {}: expected a positive number of metres", o.lidar_max_dist);
  const std::vector<std::string> forms = ObservationRewardForms();
  Require(std::find(forms.begin(), forms.end(), o.reward) != forms.end(),
          "reward is '{}'{}: expected one of {}", o.reward, DidYouMean(o.reward, forms),
          fmt::join(forms, ", "));
  Require(!o.reward_sensor.empty(), "reward_sensor is empty: expected the sensor the reward reads");
  Require(std::find(o.sensors.begin(), o.sensors.end(), o.reward_sensor) != o.sensors.end(),
          "reward_sensor is '{}'{}: expected one of the observed sensors ({})", o.reward_sensor,
          DidYouMean(o.reward_sensor, o.sensors), fmt::join(o.sensors, ", "));
  Require(o.reward != "site-distance" || !o.reward_target.empty(),
          "reward_target is empty: the site-distance reward needs the point to reach");
  Require(o.reward != "height" || o.reward_target.size() == 1,
          "reward_target has {} values: the height reward needs one, the target height",
          o.reward_target.size());
  for (const double value : o.reward_target) {
    Require(std::isfinite(value), "reward_target holds {}: expected finite numbers", value);
  }
  Require(o.reward_axis >= 0 && o.reward_axis < 1000, "reward_axis is {}: expected 0 to 999",
          o.reward_axis);
  Require(o.cost_site.empty() ? o.cost_regions.empty() : !o.cost_regions.empty(),
          "cost_site is '{}' with {} cost_regions: expected a site with at least one region, or "
          "neither",
          o.cost_site, o.cost_regions.size());
  Require(!o.cost_geoms.empty() || !o.cost_site.empty(),
          "no cost is declared: expected cost_geoms (contacts) or cost_site with cost_regions");
  Require(o.cost_geoms.empty() || o.cost_site.empty(),
          "both cost_geoms and cost_site are set: expected one kind of cost");
  Require(o.episode_steps >= 1 && o.episode_steps <= 1'000'000,
          "episode_steps is {}: expected 1 to 1000000", o.episode_steps);
  Require(o.action_repeat >= 1 && o.action_repeat <= 1000,
          "action_repeat is {}: expected 1 to 1000", o.action_repeat);
  Require(
      o.reset_low.size() == o.reset_joints.size() && o.reset_high.size() == o.reset_joints.size(),
      "reset_joints, reset_low and reset_high have {}, {} and {} entries: expected one each "
      "per joint",
      o.reset_joints.size(), o.reset_low.size(), o.reset_high.size());
  for (size_t i = 0; i < o.reset_joints.size(); ++i) {
    Require(std::isfinite(o.reset_low[i]) && std::isfinite(o.reset_high[i]) &&
                o.reset_low[i] <= o.reset_high[i],
            "joint '{}' resets in [{}, {}]: expected finite low <= high", o.reset_joints[i],
            o.reset_low[i], o.reset_high[i]);
  }
}

}  // namespace cmbrl
