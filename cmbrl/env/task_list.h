// Every task cmbrl can build, listed once (task_list.cc): its name, robot and level. The task
// specs (tasks/goal_spec.h), the environments (registry.h) and every list of task names derive
// from it. Plain data, so that configuration, sweeps and reports know the tasks without MuJoCo.
#pragma once

#include <string>
#include <vector>

namespace cmbrl {

enum class RobotKind { kPoint, kCar };

struct TaskEntry {
  std::string name;  // "PointGoal1": configs, the command line, run names
  RobotKind robot = RobotKind::kPoint;
  int level = 1;  // Safety Gym's difficulty: 1 or 2 for the Goal tasks
  // The analytic reward its MPC runs plan with (objective.reward: analytic): one of
  // planning's AnalyticRewardNames().
  std::string analytic_reward = "goal-distance";
};

// Every task, in the paper's order: PointGoal1, PointGoal2, CarGoal1, CarGoal2.
const std::vector<TaskEntry>& Tasks();

// The names of Tasks(), in its order.
std::vector<std::string> EnvNames();

// What a run's task name begins with when its environment is given from Python rather than
// built here: "python:mypackage.envs.make_arm(links=2)", "python:gymnasium:Pendulum-v1".
inline constexpr const char* kPythonTaskPrefix = "python:";

// Whether `name` names an environment given from Python.
bool IsPythonTask(const std::string& name);

// The task called `name`; throws cmbrl::Error naming it and the known ones otherwise.
const TaskEntry& FindTask(const std::string& name);

}  // namespace cmbrl
