// Every task cmbrl can build, listed once (task_list.cc): its name, family, robot and level. The
// task specs (tasks/task_spec.h), the environments (registry.h) and every list of task names
// derive from it. Plain data, so that configuration, sweeps and reports know the tasks without
// MuJoCo.
#pragma once

#include <string>
#include <vector>

namespace cmbrl {

enum class RobotKind { kPoint, kCar };

// Safety-Gymnasium's navigation families (safety_gymnasium/tasks/safe_navigation/): what the robot
// must do and which objects stand in its way. The paper ran Goal; the others exist only in the
// stock (Safety-Gymnasium) variant.
enum class TaskFamily {
  kGoal,    // drive to a goal among hazards and vases
  kButton,  // press the goal button among other buttons, hazards and moving gremlins
  kPush,    // push a box onto a goal among hazards and pillars
  kCircle,  // circle the origin along a ring, inside walls
};

// "Goal", "Button", "Push" or "Circle".
std::string FamilyName(TaskFamily family);

struct TaskEntry {
  std::string name;  // "PointGoal1": configs, the command line, run names
  TaskFamily family = TaskFamily::kGoal;
  RobotKind robot = RobotKind::kPoint;
  int level = 1;  // Safety Gym's difficulty: 1 or 2 for Goal, 0 (no constraint) to 2 otherwise
  // The analytic reward its MPC runs plan with (objective.reward: analytic): one of
  // planning's AnalyticRewardNames().
  std::string analytic_reward = "goal-distance";
};

// Whether a task exists in the paper's variants (paper, paper-lidar): the Goal family's do.
bool HasPaperVariant(const TaskEntry& task);

// Every task: the paper's four first (PointGoal1, PointGoal2, CarGoal1, CarGoal2), then Button,
// Push and Circle at levels 0 to 2, Point then Car.
const std::vector<TaskEntry>& Tasks();

// The names of Tasks(), in its order.
std::vector<std::string> EnvNames();

// The names of the paper's tasks (HasPaperVariant), in Tasks()' order: the default grid.
std::vector<std::string> PaperEnvNames();

// What a run's task name begins with when its environment is given from Python rather than
// built here: "python:mypackage.envs.make_arm(links=2)", "python:gymnasium:Pendulum-v1".
inline constexpr const char* kPythonTaskPrefix = "python:";

// Whether `name` names an environment given from Python.
bool IsPythonTask(const std::string& name);

// The task called `name`; throws cmbrl::Error naming it and the known ones otherwise.
const TaskEntry& FindTask(const std::string& name);

}  // namespace cmbrl
