#include "cmbrl/env/goal_env.h"

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

RobotDescription TaskRobot(const GoalTaskSpec& spec) {
  return spec.robot == RobotKind::kPoint ? PointRobot(spec.variant) : CarRobot(spec.variant);
}

GoalEnv::GoalEnv(GoalTaskSpec spec) : GoalEnv(spec, TaskRobot(spec)) {}

GoalEnv::GoalEnv(GoalTaskSpec spec, RobotDescription robot)
    : spec_(std::move(spec)),
      robot_(std::move(robot)),
      model_(CompileMjcf(BuildGoalWorldMjcf(spec_, robot_))),
      data_(MakeMjData(*model_)),
      rng_(0) {
  Require(spec_.frame_skip >= 1, "frame_skip must be at least 1, got {}", spec_.frame_skip);
  Require(spec_.action_repeat >= 1, "action_repeat must be at least 1, got {}",
          spec_.action_repeat);
  Require(spec_.max_env_steps >= 1, "max_env_steps must be at least 1, got {}",
          spec_.max_env_steps);
  const mjModel& m = *model_;
  robot_body_ = RequireMjId(m, mjOBJ_BODY, "robot");
  goal_mocap_ = m.body_mocapid[RequireMjId(m, mjOBJ_BODY, "goal")];
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
  if (robot_.planar_joints) {
    planar_qpos_ = {m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, "x")],
                    m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, "y")],
                    m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, "z")]};
  } else {
    free_qpos_ = m.jnt_qposadr[RequireMjId(m, mjOBJ_JOINT, "robot")];
  }
  observer_ = MakeGoalObserver(spec_, robot_, m);
  BuildSpecs();
}

void GoalEnv::BuildSpecs() {
  const int num_actuators = model_->nu;
  // Facts A4: the action box is [-1, 1] per actuator; Step clips to each actuator's ctrlrange
  // (the rover's steering servo accepts +-0.6 rad).
  action_spec_.low.assign(num_actuators, -1.0);
  action_spec_.high.assign(num_actuators, 1.0);
  action_spec_.names = robot_.action_names;

}

int GoalEnv::max_episode_steps() const {
  return (spec_.max_env_steps + spec_.action_repeat - 1) / spec_.action_repeat;
}

double GoalEnv::agent_step_seconds() const {
  return model_->opt.timestep * spec_.frame_skip * spec_.action_repeat;
}

std::vector<double> GoalEnv::Reset(std::optional<std::uint64_t> seed) {
  if (seed) rng_.seed(*seed);
  // Facts A1: a fresh layout, then the goal re-drawn against everything else. A goal that finds
  // no place (never seen in practice) gets a fresh layout rather than an exception.
  for (int attempt = 0;; ++attempt) {
    GoalLayout layout = SampleGoalLayout(spec_, rng_);
    if (ResampleGoal(spec_, layout, rng_)) return ResetToLayout(layout);
    Require(attempt + 1 < spec_.layout_tries, "no goal position fits in {} after {} layouts",
            spec_.name, spec_.layout_tries);
  }
}

std::vector<double> GoalEnv::ResetToLayout(const GoalLayout& layout) {
  Require(static_cast<int>(layout.hazards.size()) == spec_.num_hazards &&
              static_cast<int>(layout.vases.size()) == spec_.num_vases,
          "a {} layout needs {} hazards and {} vases, got {} and {}", spec_.name, spec_.num_hazards,
          spec_.num_vases, layout.hazards.size(), layout.vases.size());
  PlaceLayout(layout);
  env_steps_ = 0;
  episode_over_ = false;
  last_goal_distance_ = DistanceToGoal();
  return Observe();
}

void GoalEnv::PlaceLayout(const GoalLayout& layout) {
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
    mjtNum* qpos = d.qpos + free_qpos_;
    qpos[0] = robot.position.x;
    qpos[1] = robot.position.y;
    qpos[2] = robot_.spawn_height;
    qpos[3] = std::cos(robot.yaw / 2);
    qpos[4] = 0.0;
    qpos[5] = 0.0;
    qpos[6] = std::sin(robot.yaw / 2);
  }
  for (int i = 0; i < spec_.num_vases; ++i) {
    mjtNum* qpos = d.qpos + vase_qpos_[i];
    qpos[0] = layout.vases[i].position.x;
    qpos[1] = layout.vases[i].position.y;
    qpos[2] = spec_.vase_half_size - spec_.vase_sink;
    qpos[3] = std::cos(layout.vases[i].yaw / 2);
    qpos[4] = 0.0;
    qpos[5] = 0.0;
    qpos[6] = std::sin(layout.vases[i].yaw / 2);
  }
  MoveGoal(layout.goal);
  for (int i = 0; i < spec_.num_hazards; ++i) {
    mjtNum* pos = d.mocap_pos + 3 * hazard_mocaps_[i];
    pos[0] = layout.hazards[i].x;
    pos[1] = layout.hazards[i].y;
  }
  mj_forward(&m, &d);
}

void GoalEnv::MoveGoal(Vec2 goal) {
  layout_.goal = goal;
  mjtNum* pos = data_->mocap_pos + 3 * goal_mocap_;
  pos[0] = goal.x;
  pos[1] = goal.y;
  pos[2] = spec_.goal_size / 2 + 0.01;
  last_goal_distance_ = DistanceToGoal();
}

StepResult GoalEnv::Step(const std::vector<double>& action) {
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
  bool violated = false;
  for (int repeat = 0; repeat < spec_.action_repeat; ++repeat) {
    const EnvStepOutcome outcome = EnvStep();
    ++env_steps_;
    ++result.info.env_steps;
    result.reward += outcome.reward;
    result.info.cost_hazards += outcome.cost_hazards;
    result.info.cost_vases_contact += outcome.cost_vases_contact;
    result.info.cost_vases_velocity += outcome.cost_vases_velocity;
    violated = violated || outcome.physics_error || outcome.cost_hazards > 0.0 ||
               outcome.cost_vases_contact > 0.0 || outcome.cost_vases_velocity > 0.0;
    result.info.goal_met = result.info.goal_met || outcome.goal_met;
    result.info.physics_error = outcome.physics_error;
    result.terminated = outcome.physics_error || outcome.goal_resample_failed;
    result.truncated = !result.terminated && env_steps_ >= spec_.max_env_steps;
    // The paper's wrapper stops repeating once the goal is reached or the episode ends.
    if (outcome.goal_met || result.terminated || result.truncated) break;
  }
  result.cost = violated ? 1.0 : 0.0;
  result.info.raw_cost = result.cost;
  episode_over_ = result.terminated || result.truncated;
  result.observation = Observe();
  return result;
}

GoalEnv::EnvStepOutcome GoalEnv::EnvStep() {
  const mjModel& m = *model_;
  mjData& d = *data_;
  EnvStepOutcome outcome;
  const int warnings_before = PhysicsWarningCount();
  for (int frame = 0; frame < spec_.frame_skip; ++frame) {
    mj_step(&m, &d);
    if (PhysicsWarningCount() != warnings_before) {
      // MuJoCo reset the state after a divergence (Safety Gym: MujocoException).
      outcome.physics_error = true;
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
  ComputeCostTerms(outcome);

  const double distance = DistanceToGoal();
  outcome.reward = std::clamp((last_goal_distance_ - distance) * spec_.reward_distance,
                              -spec_.reward_clip, spec_.reward_clip);
  last_goal_distance_ = distance;
  if (distance <= spec_.goal_size) {
    outcome.goal_met = true;
    outcome.reward += spec_.reward_goal;
    // Facts A1: the layout takes the robot's and vases' current places; a new goal is drawn.
    layout_.robot = Scene().robot;
    for (int i = 0; i < spec_.num_vases; ++i) layout_.vases[i].position = VaseXY(i);
    if (ResampleGoal(spec_, layout_, rng_)) {
      MoveGoal(layout_.goal);
    } else {
      outcome.goal_resample_failed = true;
    }
  }
  return outcome;
}

void GoalEnv::ComputeCostTerms(EnvStepOutcome& outcome) const {
  const Vec2 robot = RobotXY();
  for (const Vec2& hazard : layout_.hazards) {
    const double distance = Distance(robot, hazard);
    if (distance <= spec_.hazard_size) {
      outcome.cost_hazards += spec_.hazard_cost * (spec_.hazard_size - distance);
    }
  }
  if (!spec_.vases_constrained) return;
  const mjModel& m = *model_;
  const mjData& d = *data_;
  const auto is_vase = [this](int geom) {
    return std::find(vase_geoms_.begin(), vase_geoms_.end(), geom) != vase_geoms_.end();
  };
  const auto is_robot = [this](int geom) {
    return std::find(robot_contact_geoms_.begin(), robot_contact_geoms_.end(), geom) !=
           robot_contact_geoms_.end();
  };
  for (int i = 0; i < d.ncon; ++i) {
    const int g1 = d.contact[i].geom1;
    const int g2 = d.contact[i].geom2;
    if ((is_vase(g1) && is_robot(g2)) || (is_vase(g2) && is_robot(g1))) {
      outcome.cost_vases_contact += spec_.vase_contact_cost;
    }
  }
  for (const int body : vase_bodies_) {
    mjtNum velocity[6];  // rotational then linear, world frame
    mj_objectVelocity(&m, &d, mjOBJ_BODY, body, velocity, 0);
    const double speed = std::sqrt(velocity[3] * velocity[3] + velocity[4] * velocity[4] +
                                   velocity[5] * velocity[5]);
    if (speed >= spec_.vase_velocity_threshold) {
      outcome.cost_vases_velocity += spec_.vase_velocity_cost * speed;
    }
  }
}

int GoalEnv::PhysicsWarningCount() const {
  const mjData& d = *data_;
  return d.warning[mjWARN_BADQPOS].number + d.warning[mjWARN_BADQVEL].number +
         d.warning[mjWARN_BADQACC].number;
}

RobotFrame GoalEnv::Frame() const {
  RobotFrame frame;
  std::copy_n(data_->xpos + 3 * robot_body_, 3, frame.position.begin());
  std::copy_n(data_->xmat + 9 * robot_body_, 9, frame.rotation.begin());
  return frame;
}

Vec2 GoalEnv::RobotXY() const {
  const mjtNum* pos = data_->xpos + 3 * robot_body_;
  return {pos[0], pos[1]};
}

Vec2 GoalEnv::VaseXY(int vase) const {
  const mjtNum* pos = data_->xpos + 3 * vase_bodies_[vase];
  return {pos[0], pos[1]};
}

double GoalEnv::DistanceToGoal() const { return Distance(RobotXY(), layout_.goal); }

std::vector<double> GoalEnv::Observe() const {
  GoalWorldView world;
  world.sensordata = data_->sensordata;
  world.robot = Frame();
  world.goal = layout_.goal;
  world.hazards = &layout_.hazards;
  for (int i = 0; i < spec_.num_vases; ++i) world.vases.push_back(VaseXY(i));
  std::vector<double> observation(observer_->spec().size());
  observer_->Observe(world, observation.data());
  return observation;
}

SceneState GoalEnv::Scene() const {
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
  scene.goal_radius = spec_.goal_size;
  scene.hazard_radius = spec_.hazard_size;
  scene.vase_half_size = spec_.vase_half_size;
  scene.placement = spec_.placement;
  return scene;
}

std::string GoalEnv::GeneratorState() const { return RngText(rng_); }

void GoalEnv::SetGeneratorState(const std::string& state) { rng_ = RngFromText(state); }

namespace {

constexpr const char* kStateTag = "cmbrl-goal-env-state-v1";

// mjData's fixed part before its buffers: sizes, counters, diagnostics, time (plain values).
constexpr size_t kDataHeaderBytes = offsetof(mjData, buffer);

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
std::string GoalEnv::State() const {
  ByteWriter out;
  out.Write(std::string(kStateTag));
  out.Write(spec_.name);
  out.Write(static_cast<int>(spec_.variant));
  out.Write(model_->nq);
  out.Write(model_->nv);
  out.Write(model_->nbody);
  out.WriteBytes(data_.get(), kDataHeaderBytes);
  out.WriteBytes(data_->buffer, static_cast<size_t>(data_->nbuffer));
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
  return out.Take();
}

void GoalEnv::SetState(const std::string& state) {
  const std::string what = fmt::format("the {} environment state", spec_.name);
  ByteReader in(state, what);
  Require(in.ReadString() == kStateTag, "{} is not one: expected the bytes State() wrote",
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
  const std::string_view header = in.ReadBytes(kDataHeaderBytes);
  const std::string_view buffer = in.ReadBytes(static_cast<size_t>(data_->nbuffer));
  const std::string generator = in.ReadString();
  GoalLayout layout;
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
  in.ExpectEnd();

  // Everything is read and checked: now change the environment. The header ends before mjData's
  // pointers, which stay this environment's own.
  SetGeneratorState(generator);
  std::memcpy(static_cast<void*>(data_.get()), header.data(), kDataHeaderBytes);
  std::memcpy(data_->buffer, buffer.data(), buffer.size());
  layout_ = std::move(layout);
  last_goal_distance_ = last_goal_distance;
  env_steps_ = env_steps;
  episode_over_ = episode_over;
}

}  // namespace cmbrl
