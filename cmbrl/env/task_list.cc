#include "cmbrl/env/task_list.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cmbrl/core/check.h"
#include "cmbrl/core/closest_name.h"

namespace cmbrl {
namespace {

// The analytic reward form a family's MPC runs plan with (planning/reward_term.h).
const char* FamilyReward(TaskFamily family) {
  switch (family) {
    case TaskFamily::kGoal: return "goal-distance";
    case TaskFamily::kButton: return "goal-lidar-distance";
    case TaskFamily::kPush: return "push-lidar-distances";
    case TaskFamily::kCircle: return "circle-lidar-speed";
  }
  return "";
}

std::vector<TaskEntry> AllTasks() {
  std::vector<TaskEntry> tasks;
  for (const RobotKind robot : {RobotKind::kPoint, RobotKind::kCar}) {
    for (const int level : {1, 2}) {
      tasks.push_back({fmt::format("{}Goal{}", robot == RobotKind::kPoint ? "Point" : "Car", level),
                       TaskFamily::kGoal, robot, level, FamilyReward(TaskFamily::kGoal)});
    }
  }
  for (const TaskFamily family : {TaskFamily::kButton, TaskFamily::kPush, TaskFamily::kCircle}) {
    for (const RobotKind robot : {RobotKind::kPoint, RobotKind::kCar}) {
      for (const int level : {0, 1, 2}) {
        tasks.push_back({fmt::format("{}{}{}", robot == RobotKind::kPoint ? "Point" : "Car",
                                     FamilyName(family), level),
                         family, robot, level, FamilyReward(family)});
      }
    }
  }
  return tasks;
}

}  // namespace

std::string FamilyName(TaskFamily family) {
  switch (family) {
    case TaskFamily::kGoal: return "Goal";
    case TaskFamily::kButton: return "Button";
    case TaskFamily::kPush: return "Push";
    case TaskFamily::kCircle: return "Circle";
  }
  return "";
}

bool HasPaperVariant(const TaskEntry& task) { return task.family == TaskFamily::kGoal; }

const std::vector<TaskEntry>& Tasks() {
  static const std::vector<TaskEntry> tasks = AllTasks();
  return tasks;
}

std::vector<std::string> EnvNames() {
  std::vector<std::string> names;
  for (const TaskEntry& task : Tasks()) names.push_back(task.name);
  return names;
}

std::vector<std::string> PaperEnvNames() {
  std::vector<std::string> names;
  for (const TaskEntry& task : Tasks()) {
    if (HasPaperVariant(task)) names.push_back(task.name);
  }
  return names;
}

bool IsPythonTask(const std::string& name) { return name.rfind(kPythonTaskPrefix, 0) == 0; }

const TaskEntry& FindTask(const std::string& name) {
  for (const TaskEntry& task : Tasks()) {
    if (task.name == name) return task;
  }
  Require(!IsPythonTask(name),
          "task '{}' is an environment given from Python: train, resume and load it from Python "
          "with that environment (cmbrl.train(env=...), cmbrl.load_run(..., env=...))",
          name);
  Fail("unknown task '{}'{}: expected one of {} (or an environment given from Python)", name,
       DidYouMean(name, EnvNames()), fmt::join(EnvNames(), ", "));
}

}  // namespace cmbrl
