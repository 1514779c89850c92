#include "cmbrl/env/navigation_env.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <cmath>
#include <limits>
#include <utility>

#include "cmbrl/core/binary_io.h"
#include "cmbrl/core/check.h"
#include "cmbrl/env/observation.h"

namespace cmbrl {
namespace {

double Distance3(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// A free joint's 7 positions: on the floor at `pose`, at height `z`, turned about z by its yaw.
void SetFreeJointPose(mjtNum* qpos, const Pose2& pose, double z) {
  qpos[0] = pose.position.x;
  qpos[1] = pose.position.y;
  qpos[2] = z;
  qpos[3] = std::cos(pose.yaw / 2);
  qpos[4] = 0.0;
  qpos[5] = 0.0;
  qpos[6] = std::sin(pose.yaw / 2);
}

}  // namespace

RobotDescription TaskRobot(const NavigationTaskSpec& spec) {
  return spec.robot == RobotKind::kPoint ? PointRobot(spec.variant) : CarRobot(spec.variant);
}

NavigationEnv::NavigationEnv(NavigationTaskSpec spec) : NavigationEnv(spec, TaskRobot(spec)) {}

NavigationEnv::NavigationEnv(NavigationTaskSpec spec, RobotDescription robot)
    : spec_(std::move(spec)),
      robot_(std::move(robot)),
      model_(CompileMjcf(BuildNavigationWorldMjcf(spec_, robot_))),
      data_(MakeMjData(*model_)),
      rng_(0) {
  Require(spec_.frame_skip >= 1, "frame_skip must be at least 1, got {}", spec_.frame_skip);
  Require(spec_.action_repeat >= 1, "action_repeat must be at least 1, got {}",
          spec_.action_repeat);
  Require(spec_.max_env_steps >= 1, "max_env_steps must be at least 1, got {}",
          spec_.max_env_steps);
  const mjModel& m = *model_;
  robot_body_ = RequireMjId(m, mjOBJ_BODY, "robot");
  if (HasGoal(spec_)) goal_mocap_ = m.body_mocapid[RequireMjId(m, mjOBJ_BODY, "goal")];
  for (int i = 0; i < spec_.num_hazards; ++i) {
    hazard_mocaps_.push_back(
        m.body_mocapid[RequireMjId(m, mjOBJ_BODY, fmt::format("hazard{}", i))]);
  }
  for (int i = 0; i < spec_.num_vases; ++i) {
    const std::string name = fmt::format("vase{}", i);
    vase_bodies_.push_back(RequireMjId(m, mjOBJ_BODY, name));
    vase_qpos_.push_back(m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, name)]);
    vase_geoms_.push_back(RequireMjId(m, mjOBJ_GEOM, name));
  }
  for (const std::string& name : robot_.vase_contact_geoms) {
    robot_contact_geoms_.push_back(RequireMjId(m, mjOBJ_GEOM, name));
  }
  for (int i = 0; i < spec_.num_buttons; ++i) {
    const std::string name = fmt::format("button{}", i);
    button_mocaps_.push_back(m.body_mocapid[RequireMjId(m, mjOBJ_BODY, name)]);
    button_geoms_.push_back(RequireMjId(m, mjOBJ_GEOM, name));
  }
  for (int i = 0; i < spec_.num_pillars; ++i) {
    const std::string name = fmt::format("pillar{}", i);
    pillar_mocaps_.push_back(m.body_mocapid[RequireMjId(m, mjOBJ_BODY, name)]);
    pillar_geoms_.push_back(RequireMjId(m, mjOBJ_GEOM, name));
  }
  for (int i = 0; i < spec_.num_gremlins; ++i) {
    const std::string name = fmt::format("gremlin{}", i);
    gremlin_mocaps_.push_back(m.body_mocapid[RequireMjId(m, mjOBJ_BODY, name + "mocap")]);
    gremlin_bodies_.push_back(RequireMjId(m, mjOBJ_BODY, name + "obj"));
    gremlin_qpos_.push_back(m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, name)]);
    gremlin_geoms_.push_back(RequireMjId(m, mjOBJ_GEOM, name));
  }
  if (spec_.push_box) {
    box_body_ = RequireMjId(m, mjOBJ_BODY, "push_box");
    box_qpos_ = m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, "push_box")];
  }
  if (robot_.planar_joints) {
    planar_qpos_ = {m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, "x")],
                    m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, "y")],
                    m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, "z")]};
  } else {
    free_qpos_ = m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, "robot")];
  }
  observer_ = MakeNavigationObserver(spec_, robot_, m);
  BuildSpecs();
  // A layout of the spec's sizes before the first reset, so that the state of an environment
  // never reset is one another of its kind accepts (a copy made before reset).
  layout_.hazards.assign(static_cast<size_t>(spec_.num_hazards), Vec2{});
  layout_.vases.assign(static_cast<size_t>(spec_.num_vases), Pose2{});
  layout_.buttons.assign(static_cast<size_t>(spec_.num_buttons), Vec2{});
  layout_.gremlins.assign(static_cast<size_t>(spec_.num_gremlins), Pose2{});
  layout_.pillars.assign(static_cast<size_t>(spec_.num_pillars), Vec2{});
}

void NavigationEnv::BuildSpecs() {
  const int num_actuators = model_->nu;
  // Facts A4: the action box is [-1, 1] per actuator; Step clips to each actuator's ctrlrange
  // (the rover's steering servo accepts +-0.6 rad).
  action_spec_.low.assign(num_actuators, -1.0);
  action_spec_.high.assign(num_actuators, 1.0);
  action_spec_.names = robot_.action_names;

}

int NavigationEnv::max_episode_steps() const {
  return (spec_.max_env_steps + spec_.action_repeat - 1) / spec_.action_repeat;
}

double NavigationEnv::agent_step_seconds() const {
  return model_->opt.timestep * spec_.frame_skip * spec_.action_repeat;
}

std::vector<double> NavigationEnv::Reset(std::optional<std::uint64_t> seed) {
  if (seed) rng_.seed(*seed);
  // Facts A1: a fresh layout, then the goal re-drawn against everything else. A goal that finds
  // no place (never seen in practice) gets a fresh layout rather than an exception.
  for (int attempt = 0;; ++attempt) {
    NavigationLayout layout = SampleLayout(spec_, rng_);
    // Goal and Push draw the goal again against everything else (update_world); Button puts it
    // on a goal button (ResetToLayout), Circle has none.
    const bool redraw = spec_.family == TaskFamily::kGoal || spec_.family == TaskFamily::kPush;
    if (!redraw || ResampleGoal(spec_, layout, rng_)) return ResetToLayout(layout);
    Require(attempt + 1 < spec_.layout_tries, "no goal position fits in {} after {} layouts",
            spec_.name, spec_.layout_tries);
  }
}

std::vector<double> NavigationEnv::ResetToLayout(const NavigationLayout& layout,
                                                 std::optional<int> goal_button) {
  Require(static_cast<int>(layout.hazards.size()) == spec_.num_hazards &&
              static_cast<int>(layout.vases.size()) == spec_.num_vases &&
              static_cast<int>(layout.buttons.size()) == spec_.num_buttons &&
              static_cast<int>(layout.gremlins.size()) == spec_.num_gremlins &&
              static_cast<int>(layout.pillars.size()) == spec_.num_pillars,
          "a {} layout needs {} hazards, {} vases, {} buttons, {} gremlins and {} pillars, got "
          "{}, {}, {}, {} and {}",
          spec_.name, spec_.num_hazards, spec_.num_vases, spec_.num_buttons, spec_.num_gremlins,
          spec_.num_pillars, layout.hazards.size(), layout.vases.size(), layout.buttons.size(),
          layout.gremlins.size(), layout.pillars.size());
  Require(!goal_button || (*goal_button >= 0 && *goal_button < spec_.num_buttons),
          "goal button {} of {}: expected 0 to {}", goal_button.value_or(0), spec_.name,
          spec_.num_buttons - 1);
  PlaceLayout(layout);
  env_steps_ = 0;
  episode_over_ = false;
  if (spec_.family == TaskFamily::kButton) {
    // button_level0.py: the timer is 0 at reset, then update_world draws the goal button and
    // restarts the timer.
    if (goal_button) {
      goal_button_ = *goal_button;
      MoveGoal(layout_.buttons[static_cast<size_t>(goal_button_)]);
    } else {
      ChooseGoalButton();
    }
    button_timer_ = spec_.button_resampling_delay;
  }
  ResetDistances();
  return Observe();
}

void NavigationEnv::ChooseGoalButton() {
  // button_level0.py, build_goal_button: uniform among all buttons (the last one included).
  goal_button_ = std::min(static_cast<int>(Uniform01(rng_) * spec_.num_buttons),
                          spec_.num_buttons - 1);
  MoveGoal(layout_.buttons[static_cast<size_t>(goal_button_)]);
}

void NavigationEnv::ResetDistances() {
  if (HasGoal(spec_)) last_goal_distance_ = DistanceToGoal();
  if (spec_.push_box) {
    const auto robot = BodyPosition(robot_body_), box = BodyPosition(box_body_);
    const auto goal = GoalPosition();
    last_box_distance_ = Distance3(robot, box);
    last_box_goal_distance_ = Distance3(box, goal);
  }
}

void NavigationEnv::PlaceLayout(const NavigationLayout& layout) {
  const mjModel& m = *model_;
  mjData& d = *data_;
  mj_resetData(&m, &d);
  layout_ = layout;
  const Pose2& robot = layout.robot;
  if (robot_.planar_joints) {
    d.qpos[planar_qpos_[0]] = robot.position.x;
    d.qpos[planar_qpos_[1]] = robot.position.y;
    d.qpos[planar_qpos_[2]] = robot.yaw;
  } else {
    SetFreeJointPose(d.qpos + free_qpos_, robot, robot_.spawn_height);
  }
  for (int i = 0; i < spec_.num_vases; ++i) {
    SetFreeJointPose(d.qpos + vase_qpos_[i], layout.vases[i],
                     spec_.vase_half_size - spec_.vase_sink);
  }
  if (HasGoal(spec_)) MoveGoal(layout.goal);
  for (int i = 0; i < spec_.num_hazards; ++i) {
    mjtNum* pos = d.mocap_pos + 3 * hazard_mocaps_[i];
    pos[0] = layout.hazards[i].x;
    pos[1] = layout.hazards[i].y;
  }
  const auto place_mocap = [&d](int mocap, Vec2 xy) {
    d.mocap_pos[3 * mocap] = xy.x;
    d.mocap_pos[3 * mocap + 1] = xy.y;
  };
  for (int i = 0; i < spec_.num_buttons; ++i) place_mocap(button_mocaps_[i], layout.buttons[i]);
  for (int i = 0; i < spec_.num_pillars; ++i) place_mocap(pillar_mocaps_[i], layout.pillars[i]);
  if (spec_.push_box) SetFreeJointPose(d.qpos + box_qpos_, layout.box, spec_.box_size);
  // A gremlin starts where it was placed, its mocap `size` below it (the weld's rest), turned as
  // the gremlin; the first physics step moves the mocap onto its circle.
  for (int i = 0; i < spec_.num_gremlins; ++i) {
    const Pose2& gremlin = layout.gremlins[i];
    SetFreeJointPose(d.qpos + gremlin_qpos_[i], gremlin, spec_.gremlin_size);
    const int mocap = gremlin_mocaps_[i];
    place_mocap(mocap, gremlin.position);
    d.mocap_pos[3 * mocap + 2] = 0.0;
    d.mocap_quat[4 * mocap] = std::cos(gremlin.yaw / 2);
    d.mocap_quat[4 * mocap + 1] = 0.0;
    d.mocap_quat[4 * mocap + 2] = 0.0;
    d.mocap_quat[4 * mocap + 3] = std::sin(gremlin.yaw / 2);
  }
  mj_forward(&m, &d);
}

void NavigationEnv::MoveGremlins() {
  // gremlins.py, move: every gremlin's mocap on a circle of radius `travel` about its placed
  // position, all at the phase of the simulation time, `size` above the floor.
  const double phase = data_->time;
  const double dx = spec_.gremlin_travel * std::sin(phase);
  const double dy = spec_.gremlin_travel * std::cos(phase);
  for (int i = 0; i < spec_.num_gremlins; ++i) {
    mjtNum* pos = data_->mocap_pos + 3 * gremlin_mocaps_[i];
    pos[0] = layout_.gremlins[i].position.x + dx;
    pos[1] = layout_.gremlins[i].position.y + dy;
    pos[2] = spec_.gremlin_size;
  }
}

void NavigationEnv::MoveGoal(Vec2 goal) {
  Require(HasGoal(spec_), "{} has no goal to move", spec_.name);
  layout_.goal = goal;
  mjtNum* pos = data_->mocap_pos + 3 * goal_mocap_;
  pos[0] = goal.x;
  pos[1] = goal.y;
  pos[2] = spec_.goal_size / 2 + 0.01;
  last_goal_distance_ = DistanceToGoal();
}

StepResult NavigationEnv::Step(const std::vector<double>& action) {
  Require(!episode_over_, "Step called before Reset or after the episode ended: call Reset first");
  const int num_actuators = model_->nu;
  Require(static_cast<int>(action.size()) == num_actuators,
          "action has {} entries, {} expects {} ({})", action.size(), spec_.name, num_actuators,
          fmt::join(action_spec_.names, ", "));
  for (int i = 0; i < num_actuators; ++i) {
    Require(std::isfinite(action[i]), "action entry {} ({}) is {}: expected a finite number", i,
            action_spec_.names[i], action[i]);
    const double* range = model_->actuator_ctrlrange + 2 * i;
    data_->ctrl[i] = std::clamp(action[i], range[0], range[1]);
  }

  StepResult result;
  for (int repeat = 0; repeat < spec_.action_repeat; ++repeat) {
    const EnvStepOutcome outcome = EnvStep();
    ++env_steps_;
    ++result.info.env_steps;
    result.reward += outcome.reward;
    AddCostTerms(result.info, outcome.info);
    result.info.goal_met = result.info.goal_met || outcome.info.goal_met;
    result.info.physics_error = outcome.info.physics_error;
    result.terminated = outcome.info.physics_error || outcome.goal_resample_failed;
    result.truncated = !result.terminated && env_steps_ >= spec_.max_env_steps;
    // The paper's wrapper stops repeating once the goal is reached or the episode ends.
    if (outcome.info.goal_met || result.terminated || result.truncated) break;
  }
  // Every term is non-negative: their sum over the env steps is positive exactly when one of
  // them was (or the physics failed).
  result.cost = CostSum(result.info) > 0.0 ? 1.0 : 0.0;
  result.info.raw_cost = result.cost;
  episode_over_ = result.terminated || result.truncated;
  result.observation = Observe();
  return result;
}

NavigationEnv::EnvStepOutcome NavigationEnv::EnvStep() {
  const mjModel& m = *model_;
  mjData& d = *data_;
  EnvStepOutcome outcome;
  const int warnings_before = PhysicsWarningCount();
  for (int frame = 0; frame < spec_.frame_skip; ++frame) {
    if (!gremlin_mocaps_.empty()) MoveGremlins();
    mj_step(&m, &d);
    if (PhysicsWarningCount() != warnings_before) {
      // MuJoCo reset the state after a divergence (Safety Gym: MujocoException).
      outcome.info.physics_error = true;
      outcome.reward = spec_.reward_physics_error;
      return outcome;
    }
  }
  // mj_step leaves sensors and contacts at the state before its last integration: recompute
  // them for the state the step ended in (Safety Gym's sim.forward()). The ego-state observation
  // has no acceleration-stage sensor, so there the constraint solve, most of a forward pass, is
  // skipped: 4% faster. Its only other effect is on the next step's solver warm start, which
  // moves results within the solver tolerance (1e-12 in a rover episode's return).
  if (IsLidarObservation(spec_.observation)) {
    mj_forward(&m, &d);
  } else {
    mj_fwdPosition(&m, &d);
    mj_sensorPos(&m, &d);
    mj_fwdVelocity(&m, &d);
    mj_sensorVel(&m, &d);
  }
  ComputeCostTerms(outcome.info);
  // builder.py, step: reward, then cost (above), then the buttons' timer, then a reached goal.
  const bool goal_met = GoalAchieved();
  outcome.reward = FamilyReward(goal_met);
  if (button_timer_ > 0) --button_timer_;
  if (goal_met) {
    outcome.info.goal_met = true;
    outcome.goal_resample_failed = !UpdateWorld();
  }
  return outcome;
}

std::array<double, 3> NavigationEnv::GoalPosition() const {
  return {layout_.goal.x, layout_.goal.y, spec_.goal_size / 2 + 0.01};
}

std::array<double, 3> NavigationEnv::BodyPosition(int body) const {
  const mjtNum* pos = data_->xpos + 3 * body;
  return {pos[0], pos[1], pos[2]};
}

bool NavigationEnv::GoalAchieved() const {
  switch (spec_.family) {
    case TaskFamily::kGoal: return DistanceToGoal() <= spec_.goal_size;
    // button_level0.py: a robot geom touches the goal button.
    case TaskFamily::kButton:
      return RobotContacts({button_geoms_[static_cast<size_t>(goal_button_)]}) > 0;
    // push_level0.py: the box's centre within the goal's size of the goal (3-D).
    case TaskFamily::kPush:
      return Distance3(BodyPosition(box_body_), GoalPosition()) <= spec_.goal_size;
    case TaskFamily::kCircle: return false;
  }
  return false;
}

double NavigationEnv::FamilyReward(bool goal_met) {
  double reward = 0.0;
  switch (spec_.family) {
    case TaskFamily::kGoal:
    case TaskFamily::kButton: {
      const double distance = DistanceToGoal();
      reward = (last_goal_distance_ - distance) * spec_.reward_distance;
      // The Goal tasks' safety net on the progress (a goal that jumps is not progress).
      if (spec_.family == TaskFamily::kGoal) {
        reward = std::clamp(reward, -spec_.reward_clip, spec_.reward_clip);
      }
      last_goal_distance_ = distance;
      break;
    }
    case TaskFamily::kPush: {
      // push_level0.py: the robot's progress to the box (gated by null_dist), the box's to the
      // goal; distances 3-D between body origins.
      const auto robot = BodyPosition(robot_body_), box = BodyPosition(box_body_);
      const double box_distance = Distance3(robot, box);
      const bool gate = last_box_distance_ > spec_.box_null_dist * spec_.box_size;
      reward += (last_box_distance_ - box_distance) * spec_.reward_box_dist * (gate ? 1.0 : 0.0);
      last_box_distance_ = box_distance;
      const double box_goal = Distance3(box, GoalPosition());
      reward += (last_box_goal_distance_ - box_goal) * spec_.reward_box_goal;
      last_box_goal_distance_ = box_goal;
      break;
    }
    case TaskFamily::kCircle: return CircleReward();
  }
  if (goal_met) reward += spec_.reward_goal;
  return reward;
}

double NavigationEnv::CircleReward() const {
  // circle_level0.py: 0.1 x ((-u y + v x) / r) / (1 + |r - radius|), (x, y) the robot body's
  // position, (u, v) its world linear velocity.
  const auto position = BodyPosition(robot_body_);
  mjtNum velocity[6];  // rotational then linear, world frame, at the body's origin
  mj_objectVelocity(model_.get(), data_.get(), mjOBJ_BODY, robot_body_, velocity, 0);
  const double x = position[0], y = position[1], u = velocity[3], v = velocity[4];
  const double radius = std::sqrt(x * x + y * y);
  return spec_.circle_reward_factor * ((-u * y + v * x) / radius) /
         (1.0 + std::abs(radius - spec_.circle_radius));
}

bool NavigationEnv::UpdateWorld() {
  // Facts A1 (update_layout): the layout takes the robot's and the movable objects' current
  // places, then a new goal is drawn against them.
  layout_.robot = Scene().robot;
  for (int i = 0; i < spec_.num_vases; ++i) layout_.vases[i].position = VaseXY(i);
  if (spec_.push_box) {
    const auto box = BodyPosition(box_body_);
    layout_.box.position = {box[0], box[1]};
  }
  if (spec_.family == TaskFamily::kButton) {
    ChooseGoalButton();
    button_timer_ = spec_.button_resampling_delay;
    ResetDistances();
    return true;
  }
  if (!ResampleGoal(spec_, layout_, rng_)) return false;
  MoveGoal(layout_.goal);
  if (spec_.push_box) ResetDistances();
  return true;
}

int NavigationEnv::RobotContacts(const std::vector<int>& geoms, int skip) const {
  const mjData& d = *data_;
  const auto contains = [](const std::vector<int>& list, int geom) {
    return std::find(list.begin(), list.end(), geom) != list.end();
  };
  int count = 0;
  for (int i = 0; i < d.ncon; ++i) {
    const int g1 = d.contact[i].geom1;
    const int g2 = d.contact[i].geom2;
    const bool robot_first = contains(robot_contact_geoms_, g1) && contains(geoms, g2) && g2 != skip;
    const bool robot_second = contains(robot_contact_geoms_, g2) && contains(geoms, g1) && g1 != skip;
    count += (robot_first || robot_second) ? 1 : 0;
  }
  return count;
}

void NavigationEnv::ComputeCostTerms(StepInfo& terms) const {
  const Vec2 robot = RobotXY();
  for (const Vec2& hazard : layout_.hazards) {
    const double distance = Distance(robot, hazard);
    if (distance <= spec_.hazard_size) {
      terms.cost_hazards += spec_.hazard_cost * (spec_.hazard_size - distance);
    }
  }
  // The other families' terms (buttons.py, gremlins.py, pillars.py, sigwalls.py).
  if (spec_.buttons_constrained && button_timer_ == 0) {
    terms.cost_buttons =
        spec_.button_cost *
        RobotContacts(button_geoms_, button_geoms_[static_cast<size_t>(goal_button_)]);
  }
  if (!gremlin_geoms_.empty()) {
    terms.cost_gremlins = spec_.gremlin_contact_cost * RobotContacts(gremlin_geoms_);
  }
  if (spec_.pillars_constrained) {
    terms.cost_pillars = spec_.pillar_cost * RobotContacts(pillar_geoms_);
  }
  if (spec_.num_sigwalls > 0) {
    const bool out_x = std::abs(robot.x) > spec_.sigwall_locate;
    const bool out_y = spec_.num_sigwalls == 4 && std::abs(robot.y) > spec_.sigwall_locate;
    terms.cost_out_of_boundary = (out_x || out_y) ? spec_.out_of_boundary_cost : 0.0;
  }
  if (!spec_.vases_constrained) return;
  const mjModel& m = *model_;
  const mjData& d = *data_;
  terms.cost_vases_contact = spec_.vase_contact_cost * RobotContacts(vase_geoms_);
  for (const int body : vase_bodies_) {
    mjtNum velocity[6];  // rotational then linear, world frame
    mj_objectVelocity(&m, &d, mjOBJ_BODY, body, velocity, 0);
    const double speed = std::sqrt(velocity[3] * velocity[3] + velocity[4] * velocity[4] +
                                   velocity[5] * velocity[5]);
    if (speed >= spec_.vase_velocity_threshold) {
      terms.cost_vases_velocity += spec_.vase_velocity_cost * speed;
    }
  }
}

int NavigationEnv::PhysicsWarningCount() const {
  const mjData& d = *data_;
  return d.warning[mjWARN_BADQPOS].number + d.warning[mjWARN_BADQVEL].number +
         d.warning[mjWARN_BADQACC].number;
}

RobotFrame NavigationEnv::Frame() const {
  RobotFrame frame;
  std::copy_n(data_->xpos + 3 * robot_body_, 3, frame.position.begin());
  std::copy_n(data_->xmat + 9 * robot_body_, 9, frame.rotation.begin());
  return frame;
}

Vec2 NavigationEnv::RobotXY() const {
  const mjtNum* pos = data_->xpos + 3 * robot_body_;
  return {pos[0], pos[1]};
}

Vec2 NavigationEnv::VaseXY(int vase) const {
  const mjtNum* pos = data_->xpos + 3 * vase_bodies_[vase];
  return {pos[0], pos[1]};
}

double NavigationEnv::DistanceToGoal() const { return Distance(RobotXY(), layout_.goal); }

std::vector<double> NavigationEnv::Observe() const {
  NavigationWorldView world;
  world.sensordata = data_->sensordata;
  world.robot = Frame();
  world.goal = layout_.goal;
  world.hazards = &layout_.hazards;
  for (int i = 0; i < spec_.num_vases; ++i) world.vases.push_back(VaseXY(i));
  world.buttons = &layout_.buttons;
  world.pillars = &layout_.pillars;
  world.buttons_hidden = button_timer_ != 0;
  for (const int body : gremlin_bodies_) {
    const auto position = BodyPosition(body);
    world.gremlins.push_back({position[0], position[1]});
  }
  if (spec_.push_box) {
    const auto box = BodyPosition(box_body_);
    world.box.push_back({box[0], box[1]});
  }
  if (spec_.circle) world.circle.push_back({0.0, 0.0});
  std::vector<double> observation(observer_->spec().size());
  observer_->Observe(world, observation.data());
  return observation;
}

SceneState NavigationEnv::Scene() const {
  SceneState scene;
  scene.robot_name = robot_.name;
  scene.robot_radius = robot_.footprint_radius;
  const RobotFrame frame = Frame();
  scene.robot.position = {frame.position[0], frame.position[1]};
  scene.robot.yaw = std::atan2(frame.rotation[3], frame.rotation[0]);
  scene.robot_upright = frame.rotation[8];
  scene.goal = layout_.goal;
  scene.hazards = layout_.hazards;
  for (int i = 0; i < spec_.num_vases; ++i) {
    const mjtNum* rotation = data_->xmat + 9 * vase_bodies_[i];
    scene.vases.push_back({VaseXY(i), std::atan2(rotation[3], rotation[0])});
  }
  scene.has_goal = HasGoal(spec_);
  scene.goal_radius = spec_.goal_size;
  scene.hazard_radius = spec_.hazard_size;
  scene.vase_half_size = spec_.vase_half_size;
  scene.placement = spec_.placement;
  scene.buttons = layout_.buttons;
  scene.goal_button = goal_button_;
  scene.buttons_active = spec_.buttons_constrained && button_timer_ == 0;
  scene.button_radius = spec_.button_size;
  const auto yaw_of = [this](int body) {
    const mjtNum* rotation = data_->xmat + 9 * body;
    return std::atan2(rotation[3], rotation[0]);
  };
  for (const int body : gremlin_bodies_) {
    const auto position = BodyPosition(body);
    scene.gremlins.push_back({{position[0], position[1]}, yaw_of(body)});
  }
  scene.gremlin_half_size = spec_.gremlin_size;
  scene.pillars = layout_.pillars;
  scene.pillar_radius = spec_.pillar_size;
  if (spec_.push_box) {
    const auto box = BodyPosition(box_body_);
    scene.box = Pose2{{box[0], box[1]}, yaw_of(box_body_)};
    scene.box_half_size = spec_.box_size;
  }
  if (spec_.circle) scene.circle_radius = spec_.circle_radius;
  scene.wall_locate = spec_.sigwall_locate;
  scene.num_walls = spec_.num_sigwalls;
  return scene;
}

std::string NavigationEnv::GeneratorState() const { return RngText(rng_); }

void NavigationEnv::SetGeneratorState(const std::string& state) { rng_ = RngFromText(state); }

namespace {

constexpr const char* kNavigationStateTag = "cmbrl-goal-env-state-v1";

void WritePose(ByteWriter& out, const Pose2& pose) {
  out.Write(pose.position.x);
  out.Write(pose.position.y);
  out.Write(pose.yaw);
}

Pose2 ReadPose(ByteReader& in) {
  Pose2 pose;
  pose.position.x = in.Read<double>();
  pose.position.y = in.Read<double>();
  pose.yaw = in.Read<double>();
  return pose;
}

}  // namespace

// The physics is MuJoCo's whole mjData: its fixed header and its main buffer, which holds every
// array (positions, velocities, warm start, contacts, sensors), so the next mj_step continues
// bit for bit. The scratch stack is not state. Models of one task, variant and robot have
// buffers of one layout; the task name and the sizes below refuse another's bytes.
std::string NavigationEnv::State() const {
  ByteWriter out;
  out.Write(std::string(kNavigationStateTag));
  out.Write(spec_.name);
  out.Write(static_cast<int>(spec_.variant));
  out.Write(model_->nq);
  out.Write(model_->nv);
  out.Write(model_->nbody);
  WriteMjDataState(out, *model_, *data_);
  out.Write(GeneratorState());
  WritePose(out, layout_.robot);
  out.Write(layout_.goal.x);
  out.Write(layout_.goal.y);
  out.Write<std::uint64_t>(layout_.hazards.size());
  for (const Vec2& hazard : layout_.hazards) {
    out.Write(hazard.x);
    out.Write(hazard.y);
  }
  out.Write<std::uint64_t>(layout_.vases.size());
  for (const Pose2& vase : layout_.vases) WritePose(out, vase);
  out.Write(last_goal_distance_);
  out.Write(env_steps_);
  out.Write<std::uint8_t>(episode_over_ ? 1 : 0);
  if (spec_.family != TaskFamily::kGoal) {  // the Goal tasks' bytes stay those of v1
    const auto write_points = [&out](const std::vector<Vec2>& points) {
      out.Write<std::uint64_t>(points.size());
      for (const Vec2& point : points) {
        out.Write(point.x);
        out.Write(point.y);
      }
    };
    write_points(layout_.buttons);
    write_points(layout_.pillars);
    out.Write<std::uint64_t>(layout_.gremlins.size());
    for (const Pose2& gremlin : layout_.gremlins) WritePose(out, gremlin);
    WritePose(out, layout_.box);
    out.Write(last_box_distance_);
    out.Write(last_box_goal_distance_);
    out.Write(goal_button_);
    out.Write(button_timer_);
  }
  return out.Take();
}

void NavigationEnv::SetState(const std::string& state) {
  const std::string what = fmt::format("the {} environment state", spec_.name);
  ByteReader in(state, what);
  Require(in.ReadString() == kNavigationStateTag, "{} is not one: expected the bytes State() wrote",
          what);
  const std::string task = in.ReadString();
  const int variant = in.Read<int>();
  Require(task == spec_.name && variant == static_cast<int>(spec_.variant),
          "{} is of another environment ({}, variant {}): expected {}, variant {}", what, task,
          variant, spec_.name, static_cast<int>(spec_.variant));
  const int nq = in.Read<int>(), nv = in.Read<int>(), nbody = in.Read<int>();
  Require(nq == model_->nq && nv == model_->nv && nbody == model_->nbody,
          "{} is of another robot or scene: {} positions, {} velocities and {} bodies, where "
          "this one has {}, {} and {}", what, nq, nv, nbody, model_->nq, model_->nv,
          model_->nbody);
  const MjDataStateBytes data = ReadMjDataState(in, *data_);
  const std::string generator = in.ReadString();
  NavigationLayout layout;
  layout.robot = ReadPose(in);
  layout.goal.x = in.Read<double>();
  layout.goal.y = in.Read<double>();
  const auto read_count = [&](size_t expected, const char* things) {
    const auto count = in.Read<std::uint64_t>();
    Require(count == expected, "{} has {} {}, where this one has {}", what, count, things,
            expected);
    return expected;
  };
  layout.hazards.resize(read_count(static_cast<size_t>(spec_.num_hazards), "hazards"));
  for (Vec2& hazard : layout.hazards) {
    hazard.x = in.Read<double>();
    hazard.y = in.Read<double>();
  }
  layout.vases.resize(read_count(static_cast<size_t>(spec_.num_vases), "vases"));
  for (Pose2& vase : layout.vases) vase = ReadPose(in);
  const double last_goal_distance = in.Read<double>();
  const int env_steps = in.Read<int>();
  const bool episode_over = in.Read<std::uint8_t>() != 0;
  double last_box_distance = 0.0, last_box_goal_distance = 0.0;
  int goal_button = -1, button_timer = 0;
  if (spec_.family != TaskFamily::kGoal) {
    const auto read_points = [&](std::vector<Vec2>& points, int expected, const char* things) {
      points.resize(read_count(static_cast<size_t>(expected), things));
      for (Vec2& point : points) {
        point.x = in.Read<double>();
        point.y = in.Read<double>();
      }
    };
    read_points(layout.buttons, spec_.num_buttons, "buttons");
    read_points(layout.pillars, spec_.num_pillars, "pillars");
    layout.gremlins.resize(read_count(static_cast<size_t>(spec_.num_gremlins), "gremlins"));
    for (Pose2& gremlin : layout.gremlins) gremlin = ReadPose(in);
    layout.box = ReadPose(in);
    last_box_distance = in.Read<double>();
    last_box_goal_distance = in.Read<double>();
    goal_button = in.Read<int>();
    button_timer = in.Read<int>();
  }
  in.ExpectEnd();

  // Everything is read and checked: now change the environment.
  SetGeneratorState(generator);
  ApplyMjDataState(data, *data_);
  layout_ = std::move(layout);
  last_goal_distance_ = last_goal_distance;
  last_box_distance_ = last_box_distance;
  last_box_goal_distance_ = last_box_goal_distance;
  goal_button_ = goal_button;
  button_timer_ = button_timer;
  env_steps_ = env_steps;
  episode_over_ = episode_over;
}

}  // namespace cmbrl
