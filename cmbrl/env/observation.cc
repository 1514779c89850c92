#include "cmbrl/env/observation.h"

#include <algorithm>
#include <cmath>

namespace cmbrl {

Vec2 EgoXY(const RobotFrame& robot, Vec2 point) {
  // The target's z is 0, the robot's is its body height: relevant only when the robot tilts.
  const double offset[3] = {point.x - robot.position[0], point.y - robot.position[1],
                            -robot.position[2]};
  const auto& r = robot.rotation;
  return {offset[0] * r[0] + offset[1] * r[3] + offset[2] * r[6],
          offset[0] * r[1] + offset[1] * r[4] + offset[2] * r[7]};
}

void PseudoLidar(const RobotFrame& robot, const std::vector<Vec2>& objects, int bins,
                 double max_dist, double* out) {
  std::fill(out, out + bins, 0.0);
  const double bin_size = 2.0 * M_PI / bins;
  for (const Vec2 object : objects) {
    const Vec2 ego = EgoXY(robot, object);
    double angle = std::atan2(ego.y, ego.x);
    if (angle < 0.0) angle += 2.0 * M_PI;
    // atan2 of a tiny negative y can round to exactly 2 pi after the shift.
    int bin = static_cast<int>(angle / bin_size);
    if (bin >= bins) bin = bins - 1;
    const double reading = std::max(0.0, max_dist - Norm(ego)) / max_dist;
    out[bin] = std::max(out[bin], reading);
    const double alias = (angle - bin * bin_size) / bin_size;
    const int next = (bin + 1) % bins;
    const int previous = (bin + bins - 1) % bins;
    out[next] = std::max(out[next], alias * reading);
    out[previous] = std::max(out[previous], (1.0 - alias) * reading);
  }
}

}  // namespace cmbrl
