#include "cmbrl/env/navigation_observer.h"

#include <fmt/format.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <limits>
#include <string>

#include "cmbrl/core/check.h"

namespace cmbrl {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void AppendNames(BoxSpec& box, const std::string& key, int count, double low, double high) {
  static const char* const kAxes[] = {"x", "y", "z"};
  for (int i = 0; i < count; ++i) {
    box.low.push_back(low);
    box.high.push_back(high);
    box.names.push_back(count == 1   ? key
                        : count <= 3 ? fmt::format("{}_{}", key, kAxes[i])
                                     : fmt::format("{}_{}", key, i));
  }
}

struct SensorSlot {
  int address = -1;
  int size = 0;
};

SensorSlot Sensor(const mjModel& m, const std::string& name) {
  const int id = RequireMjId(m, mjOBJ_SENSOR, name);
  return SensorSlot{m.sensor_adr[id], m.sensor_dim[id]};
}

// Facts B1: [velocimeter x, y | gyro z | magnetometer | goal | vases | hazards] in ego XY (the
// car's magnetometer comes before its gyro).
class EgoStateObserver final : public NavigationObserver {
 public:
  EgoStateObserver(const NavigationTaskSpec& spec, const RobotDescription& robot, const mjModel& m)
      : magnetometer_before_gyro_(robot.magnetometer_before_gyro),
        velocimeter_(Sensor(m, "velocimeter")),
        gyro_(Sensor(m, "gyro")),
        magnetometer_(Sensor(m, "magnetometer")) {
    AppendNames(spec_, "velocimeter", 2, -kInf, kInf);
    if (magnetometer_before_gyro_) {
      AppendNames(spec_, "magnetometer", 3, -kInf, kInf);
      AppendNames(spec_, "gyro_z", 1, -kInf, kInf);
    } else {
      AppendNames(spec_, "gyro_z", 1, -kInf, kInf);
      AppendNames(spec_, "magnetometer", 3, -kInf, kInf);
    }
    AppendNames(spec_, "goal", 2, -kInf, kInf);
    for (int i = 0; i < spec.num_vases; ++i) {
      AppendNames(spec_, fmt::format("vase{}", i), 2, -kInf, kInf);
    }
    for (int i = 0; i < spec.num_hazards; ++i) {
      AppendNames(spec_, fmt::format("hazard{}", i), 2, -kInf, kInf);
    }
  }

  const BoxSpec& spec() const override { return spec_; }

  void Observe(const NavigationWorldView& world, double* out) const override {
    const double* sensors = world.sensordata;
    *out++ = sensors[velocimeter_.address];
    *out++ = sensors[velocimeter_.address + 1];
    const double gyro_z = sensors[gyro_.address + 2];
    if (!magnetometer_before_gyro_) *out++ = gyro_z;
    out = std::copy_n(sensors + magnetometer_.address, 3, out);
    if (magnetometer_before_gyro_) *out++ = gyro_z;
    const auto put = [&out, &world](Vec2 point) {
      const Vec2 ego = EgoXY(world.robot, point);
      *out++ = ego.x;
      *out++ = ego.y;
    };
    put(world.goal);
    for (const Vec2& vase : world.vases) put(vase);
    for (const Vec2& hazard : *world.hazards) put(hazard);
  }

 private:
  bool magnetometer_before_gyro_;
  SensorSlot velocimeter_, gyro_, magnetometer_;
  BoxSpec spec_;
};

// Facts A5: named blocks; sensors raw (a ball quaternion as its 3 x 3 matrix), lidars as Safety
// Gym's pseudo-lidar. In Safety-Gymnasium's order (safety_gymnasium/bases/base_task.py,
// build_observation_space, flattening an OrderedDict): the agent's sensors in SensorConf's order,
// its joint sensors (angular velocities before quaternions, base_agent.py), then a lidar per
// kind of object in the order the task adds them (LidarObjects). The
// original Safety Gym flattened the same blocks in alphabetical order of their keys
// (kLidarSorted).
class LidarObserver final : public NavigationObserver {
 public:
  LidarObserver(const NavigationTaskSpec& spec, const RobotDescription& robot, const mjModel& m)
      : bins_(spec.lidar_bins), max_dist_(spec.lidar_max_dist) {
    blocks_.push_back({"accelerometer", Kind::kSensor, Sensor(m, "accelerometer"), 3});
    blocks_.push_back({"velocimeter", Kind::kSensor, Sensor(m, "velocimeter"), 3});
    blocks_.push_back({"gyro", Kind::kSensor, Sensor(m, "gyro"), 3});
    blocks_.push_back({"magnetometer", Kind::kSensor, Sensor(m, "magnetometer"), 3});
    for (const std::string& name : robot.joint_observation_sensors) {  // in Safety-Gymnasium's order
      const bool quat = name.rfind("ballquat", 0) == 0;
      const SensorSlot slot = Sensor(m, name);
      blocks_.push_back({name, quat ? Kind::kBallQuat : Kind::kSensor, slot, quat ? 9 : slot.size});
    }
    for (const LidarObject object : LidarObjects(spec)) {
      blocks_.push_back({LidarKey(object), Kind::kLidar, {}, bins_, object});
    }
    if (spec.observation == ObservationKind::kLidarSorted) {
      std::stable_sort(blocks_.begin(), blocks_.end(),
                       [](const Block& a, const Block& b) { return a.key < b.key; });
    }
    for (const Block& block : blocks_) {
      const bool lidar = block.kind == Kind::kLidar;
      AppendNames(spec_, block.key, block.size, lidar ? 0.0 : -kInf, lidar ? 1.0 : kInf);
    }
  }

  const BoxSpec& spec() const override { return spec_; }

  void Observe(const NavigationWorldView& world, double* out) const override {
    for (const Block& block : blocks_) {
      switch (block.kind) {
        case Kind::kSensor:
          std::copy_n(world.sensordata + block.sensor.address, block.size, out);
          break;
        case Kind::kBallQuat: {
          mjtNum matrix[9];
          mju_quat2Mat(matrix, world.sensordata + block.sensor.address);
          std::copy_n(matrix, 9, out);
          break;
        }
        case Kind::kLidar:
          ObserveLidar(world, block.object, out);
          break;
      }
      out += block.size;
    }
  }

 private:
  enum class Kind { kSensor, kBallQuat, kLidar };
  struct Block {
    std::string key;
    Kind kind = Kind::kSensor;
    SensorSlot sensor;  // for kSensor and kBallQuat
    int size = 0;       // values written
    LidarObject object = LidarObject::kGoal;  // for kLidar
  };

  void ObserveLidar(const NavigationWorldView& world, LidarObject object, double* out) const {
    switch (object) {
      case LidarObject::kGoal:
        PseudoLidar(world.robot, {world.goal}, bins_, max_dist_, out);
        return;
      case LidarObject::kHazards:
        PseudoLidar(world.robot, *world.hazards, bins_, max_dist_, out);
        return;
      case LidarObject::kVases:
        PseudoLidar(world.robot, world.vases, bins_, max_dist_, out);
        return;
      case LidarObject::kButtons:
        if (world.buttons_hidden) {
          std::fill(out, out + bins_, 0.0);
        } else {
          PseudoLidar(world.robot, *world.buttons, bins_, max_dist_, out);
        }
        return;
      case LidarObject::kGremlins:
        PseudoLidar(world.robot, world.gremlins, bins_, max_dist_, out);
        return;
      case LidarObject::kPillars:
        PseudoLidar(world.robot, *world.pillars, bins_, max_dist_, out);
        return;
      case LidarObject::kPushBox:
        PseudoLidar(world.robot, world.box, bins_, max_dist_, out);
        return;
      case LidarObject::kCircle:
        PseudoLidar(world.robot, world.circle, bins_, max_dist_, out);
        return;
    }
  }
  int bins_;
  double max_dist_;
  std::vector<Block> blocks_;
  BoxSpec spec_;
};

}  // namespace

std::unique_ptr<NavigationObserver> MakeNavigationObserver(const NavigationTaskSpec& spec,
                                               const RobotDescription& robot,
                                               const mjModel& model) {
  if (IsLidarObservation(spec.observation)) {
    return std::make_unique<LidarObserver>(spec, robot, model);
  }
  return std::make_unique<EgoStateObserver>(spec, robot, model);
}

}  // namespace cmbrl
