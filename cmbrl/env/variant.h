// Which version of the Safety Gym Goal tasks an environment re-creates.
#pragma once

#include <string>

namespace cmbrl {

enum class Variant {
  kPaper,     // the modified suite the paper's code ran (facts B0, B1): the default
  kStandard,  // Safety-Gymnasium's stock tasks (facts A1 to A6)
  // The paper's world (layout, robots, costs, 30 s episodes) as its model-free baselines saw it:
  // Safety Gym's own observation (sensors and pseudo-lidar) and no action repeat.
  kPaperLidar,
};

// Whether a variant is the paper's modified world (kPaper, kPaperLidar).
bool IsPaperWorld(Variant variant);

// "paper", "standard" or "paper-lidar".
std::string VariantName(Variant variant);

// Parses a variant's name; throws cmbrl::Error naming the value otherwise.
Variant ParseVariant(const std::string& name);

}  // namespace cmbrl
