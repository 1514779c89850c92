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

bool IsPythonTask(const std::string& name) { return name.rfind(kPythonTaskPrefix, 0) == 0; }

const TaskEntry& FindTask(const std::string& name) {
  for (const TaskEntry& task : Tasks()) {
    if (task.name == name) return task;
  }
  Require(!IsPythonTask(name),
          "task '{}' is an environment given from Python: train, resume and load it from Python "
          "with that environment (cmbrl.train(env=...), cmbrl.load_run(..., env=...))",
          name);
  Fail("unknown task '{}': expected one of {} (or an environment given from Python)", name,
       fmt::join(EnvNames(), ", "));
}

}  // namespace cmbrl
