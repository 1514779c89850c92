#include "cmbrl/env/registry.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "cmbrl/core/check.h"
#include "cmbrl/core/memory.h"
#include "cmbrl/env/navigation_env.h"
#include "cmbrl/env/tasks/task_spec.h"

namespace cmbrl {

std::unique_ptr<Env> MakeEnv(const std::string& task, Variant variant, Spawn spawn) {
  const NavigationTaskSpec spec = NavigationTaskSpecByName(task, variant);
  RobotDescription robot = TaskRobot(spec);
  if (spawn == Spawn::kModelOrigin) robot.spawn_height = robot.model_origin_height;
  return std::make_unique<NavigationEnv>(spec, std::move(robot));
}

std::vector<std::unique_ptr<Env>> MakeEnvs(const std::string& task, Variant variant, Spawn spawn,
                                           int count) {
  Require(count >= 1, "num_envs is {}: expected at least 1", count);
  // The process's resident memory: what an environment's pages take once touched (MuJoCo
  // allocates a stack it rarely fills, so the heap's count is several times more).
  const auto resident = [] {
    long pages = 0, resident = 0;
    if (std::FILE* statm = std::fopen("/proc/self/statm", "r")) {
      if (std::fscanf(statm, "%ld %ld", &pages, &resident) != 2) resident = 0;
      std::fclose(statm);
    }
    return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  };
  std::vector<std::unique_ptr<Env>> envs;
  envs.push_back(MakeEnv(task, variant, spawn));
  if (count == 1) return envs;
  // The second environment's share: the first also pays what the process makes once.
  const double before = resident();
  envs.push_back(MakeEnv(task, variant, spawn));
  // At least a MiB, should the pages have been resident already (memory freed and reused).
  const double each = std::max(resident() - before, 1024.0 * 1024.0);
  RequireMemory(each * count,
                fmt::format("num_envs {}: {} environments of {} ({:.1f} MiB each)", count, count,
                            task, each / (1024.0 * 1024.0)),
                "use fewer environments");
  envs.reserve(static_cast<size_t>(count));
  for (int k = 2; k < count; ++k) envs.push_back(MakeEnv(task, variant, spawn));
  return envs;
}

}  // namespace cmbrl
