#include "cmbrl/env/mujoco_task.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>

#include "cmbrl/core/binary_io.h"
#include "cmbrl/core/check.h"
#include "cmbrl/env/observation.h"

namespace cmbrl {
namespace {

constexpr const char* kTaskStateTag = "cmbrl-mujoco-task-state-v1";

// The model's names of one kind, for messages.
std::string NamesOf(const mjModel& m, mjtObj type, int count) {
  std::vector<std::string> names;
  for (int i = 0; i < count; ++i) {
    const char* name = mj_id2name(&m, type, i);
    if (name != nullptr && *name != '\0') names.push_back(name);
  }
  return names.empty() ? "none" : fmt::format("{}", fmt::join(names, ", "));
}

// The id of `name` of `type`; throws naming the key, the name and the model's names.
int IdOf(const mjModel& m, mjtObj type, int count, const std::string& name, const char* key,
         const char* kind) {
  const int id = mj_name2id(&m, type, name.c_str());
  Require(id >= 0, "mujoco_task.{}: the model has no {} named '{}' (its {}s: {})", key, kind, name,
          kind, NamesOf(m, type, count));
  return id;
}

MjModelPtr LoadModel(const std::string& path) {
  SilenceMujocoWarnings();
  std::array<char, 1024> error{};
  mjModel* model = mj_loadXML(path.c_str(), nullptr, error.data(), static_cast<int>(error.size()));
  Require(model != nullptr, "mujoco_task.model: MuJoCo cannot load '{}': {}", path, error.data());
  return MjModelPtr(model);
}

}  // namespace

double ObservationReward(const MujocoTaskOptions& o, const double* values, int width) {
  if (o.reward == "site-distance") {
    double sum = 0.0;
    for (size_t i = 0; i < o.reward_target.size(); ++i) {
      const double d = values[i] - o.reward_target[i];
      sum += d * d;
    }
    return -std::sqrt(sum);
  }
  Require(o.reward_axis < width, "reward_axis {} is outside the sensor's {} values", o.reward_axis,
          width);
  if (o.reward == "speed-along") return values[o.reward_axis];
  return -std::abs(values[o.reward_axis] - o.reward_target[0]);  // height
}

MujocoTaskEnv::MujocoTaskEnv(MujocoTaskOptions options, std::string task)
    : options_(std::move(options)), task_(std::move(task)) {
  ValidateMujocoTaskOptions(options_);
  model_ = LoadModel(options_.model);
  data_ = MakeMjData(*model_);
  ResolveSensors();
  ResolveLidar();
  ResolveCost();
  const mjModel& m = *model_;
  for (const std::string& name : options_.reset_joints) {
    const int id = IdOf(m, mjOBJ_JOINT, m.njnt, name, "reset_joints", "joint");
    Require(m.jnt_type[id] == mjJNT_HINGE || m.jnt_type[id] == mjJNT_SLIDE,
            "mujoco_task.reset_joints: joint '{}' is not a hinge or slide joint", name);
    reset_qpos_.push_back(m.jnt_qposadr[id]);
  }
  Require(m.nu >= 1, "mujoco_task.model: '{}' has no actuator to act with", options_.model);
  for (int i = 0; i < m.nu; ++i) {
    const char* name = mj_id2name(&m, mjOBJ_ACTUATOR, i);
    Require(m.actuator_ctrllimited[i] != 0,
            "mujoco_task.model: actuator '{}' has no ctrlrange: cmbrl plans in a finite box",
            name != nullptr ? name : std::to_string(i));
    action_spec_.names.push_back(name != nullptr && *name != '\0' ? name
                                                                  : fmt::format("actuator_{}", i));
    action_spec_.low.push_back(-1.0);
    action_spec_.high.push_back(1.0);
  }
}

void MujocoTaskEnv::ResolveSensors() {
  const mjModel& m = *model_;
  for (const std::string& name : options_.sensors) {
    const int id = IdOf(m, mjOBJ_SENSOR, m.nsensor, name, "sensors", "sensor");
    sensors_.push_back(id);
    if (name == options_.reward_sensor) {
      reward_offset_ = observation_spec_.size();
      reward_width_ = m.sensor_dim[id];
    }
    for (int k = 0; k < m.sensor_dim[id]; ++k) {
      observation_spec_.names.push_back(fmt::format("{}_{}", name, k));
      observation_spec_.low.push_back(-INFINITY);
      observation_spec_.high.push_back(INFINITY);
    }
  }
  Require(options_.reward != "site-distance" ||
              static_cast<int>(options_.reward_target.size()) == reward_width_,
          "mujoco_task.reward_target has {} values: sensor '{}' gives {}",
          options_.reward_target.size(), options_.reward_sensor, reward_width_);
  Require(options_.reward == "site-distance" || options_.reward_axis < reward_width_,
          "mujoco_task.reward_axis is {}: sensor '{}' gives {} values", options_.reward_axis,
          options_.reward_sensor, reward_width_);
}

void MujocoTaskEnv::ResolveLidar() {
  const mjModel& m = *model_;
  if (options_.lidar_groups.empty()) return;
  lidar_body_ = IdOf(m, mjOBJ_BODY, m.nbody, options_.lidar_body, "lidar_body", "body");
  for (const std::string& entry : options_.lidar_groups) {
    const LidarGroup group = ParseLidarGroup(entry);
    std::vector<int> bodies;
    for (const std::string& body : group.bodies) {
      bodies.push_back(IdOf(m, mjOBJ_BODY, m.nbody, body, "lidar_groups", "body"));
    }
    lidar_groups_.push_back(std::move(bodies));
    for (int k = 0; k < options_.lidar_bins; ++k) {
      observation_spec_.names.push_back(fmt::format("{}_lidar_{}", group.name, k));
      observation_spec_.low.push_back(0.0);
      observation_spec_.high.push_back(1.0);
    }
  }
}

void MujocoTaskEnv::ResolveCost() {
  const mjModel& m = *model_;
  for (const std::string& name : options_.cost_geoms) {
    cost_geoms_.push_back(IdOf(m, mjOBJ_GEOM, m.ngeom, name, "cost_geoms", "geom"));
  }
  for (const std::string& name : options_.cost_contact_with) {
    cost_with_.push_back(IdOf(m, mjOBJ_GEOM, m.ngeom, name, "cost_contact_with", "geom"));
  }
  if (!options_.cost_site.empty()) {
    cost_site_ = IdOf(m, mjOBJ_SITE, m.nsite, options_.cost_site, "cost_site", "site");
  }
  for (const std::string& name : options_.cost_regions) {
    const int id = IdOf(m, mjOBJ_GEOM, m.ngeom, name, "cost_regions", "geom");
    const int type = m.geom_type[id];
    Require(type == mjGEOM_SPHERE || type == mjGEOM_BOX || type == mjGEOM_CYLINDER ||
                type == mjGEOM_CAPSULE,
            "mujoco_task.cost_regions: geom '{}' is of a shape a site cannot be tested inside "
            "(expected a sphere, box, cylinder or capsule)",
            name);
    cost_regions_.push_back(id);
  }
}

double MujocoTaskEnv::agent_step_seconds() const {
  return model_->opt.timestep * options_.action_repeat;
}

std::vector<double> MujocoTaskEnv::Observe() const {
  std::vector<double> observation;
  observation.reserve(observation_spec_.size());
  for (const int id : sensors_) {
    const mjtNum* values = data_->sensordata + model_->sensor_adr[id];
    observation.insert(observation.end(), values, values + model_->sensor_dim[id]);
  }
  if (lidar_groups_.empty()) return observation;
  RobotFrame frame;
  std::copy_n(data_->xpos + 3 * lidar_body_, 3, frame.position.begin());
  std::copy_n(data_->xmat + 9 * lidar_body_, 9, frame.rotation.begin());
  for (const std::vector<int>& group : lidar_groups_) {
    std::vector<Vec2> objects;
    for (const int body : group) {
      objects.push_back({data_->xpos[3 * body], data_->xpos[3 * body + 1]});
    }
    const size_t at = observation.size();
    observation.resize(at + static_cast<size_t>(options_.lidar_bins));
    PseudoLidar(frame, objects, options_.lidar_bins, options_.lidar_max_dist, &observation[at]);
  }
  return observation;
}

bool MujocoTaskEnv::SiteInRegion(int region) const {
  const mjModel& m = *model_;
  const mjtNum* site = data_->site_xpos + 3 * cost_site_;
  const mjtNum* centre = data_->geom_xpos + 3 * region;
  const mjtNum* frame = data_->geom_xmat + 9 * region;  // row-major: local axes are columns
  mjtNum offset[3] = {site[0] - centre[0], site[1] - centre[1], site[2] - centre[2]};
  mjtNum local[3];
  mju_mulMatTVec(local, frame, offset, 3, 3);
  const mjtNum* size = m.geom_size + 3 * region;
  switch (m.geom_type[region]) {
    case mjGEOM_SPHERE:
      return mju_norm3(local) < size[0];
    case mjGEOM_BOX:
      return std::abs(local[0]) < size[0] && std::abs(local[1]) < size[1] &&
             std::abs(local[2]) < size[2];
    case mjGEOM_CYLINDER:
      return std::hypot(local[0], local[1]) < size[0] && std::abs(local[2]) < size[1];
    default: {  // capsule: within size[0] of its axis segment of half-length size[1]
      const mjtNum z = std::clamp<mjtNum>(local[2], -size[1], size[1]);
      return std::hypot(local[0], local[1], local[2] - z) < size[0];
    }
  }
}

bool MujocoTaskEnv::Violated() const {
  if (cost_site_ >= 0) {
    return std::any_of(cost_regions_.begin(), cost_regions_.end(),
                       [&](int region) { return SiteInRegion(region); });
  }
  const auto listed = [](const std::vector<int>& ids, int geom) {
    return std::find(ids.begin(), ids.end(), geom) != ids.end();
  };
  for (int c = 0; c < data_->ncon; ++c) {
    const int a = data_->contact[c].geom1, b = data_->contact[c].geom2;
    const auto touches = [&](int mine, int other) {
      return listed(cost_geoms_, mine) && (cost_with_.empty() || listed(cost_with_, other));
    };
    if (touches(a, b) || touches(b, a)) return true;
  }
  return false;
}

std::vector<double> MujocoTaskEnv::Reset(std::optional<std::uint64_t> seed) {
  if (seed) rng_.seed(*seed);
  mj_resetData(model_.get(), data_.get());
  for (size_t i = 0; i < reset_qpos_.size(); ++i) {
    data_->qpos[reset_qpos_[i]] += Uniform(rng_, options_.reset_low[i], options_.reset_high[i]);
  }
  mj_forward(model_.get(), data_.get());
  steps_ = 0;
  return Observe();
}

StepResult MujocoTaskEnv::Step(const std::vector<double>& action) {
  Require(static_cast<int>(action.size()) == action_spec_.size(),
          "the action has {} entries: expected {}", action.size(), action_spec_.size());
  const mjModel& m = *model_;
  for (int i = 0; i < m.nu; ++i) {
    Require(std::isfinite(action[i]), "action entry {} ({}) is {}: expected a finite number", i,
            action_spec_.names[i], action[i]);
    const double a = std::clamp(action[i], -1.0, 1.0);
    const double* range = m.actuator_ctrlrange + 2 * i;
    data_->ctrl[i] = range[0] + (a + 1.0) * 0.5 * (range[1] - range[0]);
  }
  StepResult result;
  bool violated = false;
  for (int repeat = 0; repeat < options_.action_repeat; ++repeat) {
    mj_step(model_.get(), data_.get());
    violated = violated || Violated();  // mj_step leaves contacts of the state it began from
    ++result.info.env_steps;
  }
  mj_forward(model_.get(), data_.get());  // sensors, contacts and sites of the state reached
  violated = violated || Violated();
  ++steps_;
  result.observation = Observe();
  bool finite = true;
  for (const double value : result.observation) finite = finite && std::isfinite(value);
  result.info.physics_error = !finite;
  result.terminated = !finite;
  result.truncated = !result.terminated && steps_ >= options_.episode_steps;
  if (!finite) std::fill(result.observation.begin(), result.observation.end(), 0.0);
  result.reward = finite ? ObservationReward(options_, result.observation.data() + reward_offset_,
                                             reward_width_)
                         : 0.0;
  result.cost = violated ? 1.0 : 0.0;
  result.info.raw_cost = result.cost;
  return result;
}

std::string MujocoTaskEnv::GeneratorState() const { return RngText(rng_); }

void MujocoTaskEnv::SetGeneratorState(const std::string& state) { rng_ = RngFromText(state); }

// MuJoCo's whole mjData (its fixed header and main buffer), the generator and the step count.
std::string MujocoTaskEnv::State() const {
  ByteWriter out;
  out.Write(std::string(kTaskStateTag));
  out.Write(task_);
  out.Write(model_->nq);
  out.Write(model_->nv);
  out.Write(static_cast<std::uint64_t>(data_->nbuffer));
  WriteMjDataState(out, *model_, *data_);
  out.Write(GeneratorState());
  out.Write(steps_);
  return out.Take();
}

void MujocoTaskEnv::SetState(const std::string& state) {
  const std::string what = fmt::format("the {} environment state", task_);
  ByteReader in(state, what);
  Require(in.ReadString() == kTaskStateTag, "{} is not one: expected the bytes State() wrote",
          what);
  const std::string task = in.ReadString();
  const int nq = in.Read<int>(), nv = in.Read<int>();
  const auto nbuffer = in.Read<std::uint64_t>();
  Require(task == task_ && nq == model_->nq && nv == model_->nv &&
              nbuffer == static_cast<std::uint64_t>(data_->nbuffer),
          "{} is of another task or model ({})", what, task);
  const MjDataStateBytes data = ReadMjDataState(in, *data_);
  const std::string generator = in.ReadString();
  const int steps = in.Read<int>();
  in.ExpectEnd();
  SetGeneratorState(generator);
  ApplyMjDataState(data, *data_);
  steps_ = steps;
}

}  // namespace cmbrl
