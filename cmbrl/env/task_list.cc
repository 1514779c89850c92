#include "cmbrl/env/task_list.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cmbrl/core/check.h"

namespace cmbrl {

const std::vector<TaskEntry>& Tasks() {
  static const std::vector<TaskEntry> tasks = {
      {"PointGoal1", RobotKind::kPoint, 1, "goal-distance"},
      {"PointGoal2", RobotKind::kPoint, 2, "goal-distance"},
      {"CarGoal1", RobotKind::kCar, 1, "goal-distance"},
      {"CarGoal2", RobotKind::kCar, 2, "goal-distance"},
  };
  return tasks;
}

std::vector<std::string> EnvNames() {
  std::vector<std::string> names;
  for (const TaskEntry& task : Tasks()) names.push_back(task.name);
  return names;
}

const TaskEntry& FindTask(const std::string& name) {
  for (const TaskEntry& task : Tasks()) {
    if (task.name == name) return task;
  }
  Fail("unknown task '{}': expected one of {}", name, fmt::join(EnvNames(), ", "));
}

}  // namespace cmbrl
