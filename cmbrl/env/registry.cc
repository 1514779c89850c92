#include "cmbrl/env/registry.h"

#include <fmt/format.h>
#include <malloc.h>

#include <algorithm>

#include "cmbrl/core/check.h"
#include "cmbrl/core/memory.h"
#include "cmbrl/env/goal_env.h"
#include "cmbrl/env/tasks/goal_spec.h"

namespace cmbrl {

std::unique_ptr<Env> MakeEnv(const std::string& task, Variant variant, Spawn spawn) {
  const GoalTaskSpec spec = GoalTaskSpecByName(task, variant);
  RobotDescription robot = TaskRobot(spec);
  if (spawn == Spawn::kModelOrigin) robot.spawn_height = robot.model_origin_height;
  return std::make_unique<GoalEnv>(spec, std::move(robot));
}

std::vector<std::unique_ptr<Env>> MakeEnvs(const std::string& task, Variant variant, Spawn spawn,
                                           int count) {
  Require(count >= 1, "num_envs is {}: expected at least 1", count);
  // The heap in use (small blocks and mmapped large ones), before and after the first one.
  const auto heap = [] {
    const struct mallinfo2 info = mallinfo2();
    return static_cast<double>(info.uordblks) + static_cast<double>(info.hblkhd);
  };
  std::vector<std::unique_ptr<Env>> envs;
  const double before = heap();
  envs.push_back(MakeEnv(task, variant, spawn));
  // At least the simulator's own buffers, should the allocator's count miss them.
  const double each = std::max(heap() - before, 1024.0 * 1024.0);
  RequireMemory(each * count,
                fmt::format("num_envs {}: {} environments of {} ({:.1f} MiB each)", count, count,
                            task, each / (1024.0 * 1024.0)),
                "use fewer environments");
  envs.reserve(static_cast<size_t>(count));
  for (int k = 1; k < count; ++k) envs.push_back(MakeEnv(task, variant, spawn));
  return envs;
}

}  // namespace cmbrl
