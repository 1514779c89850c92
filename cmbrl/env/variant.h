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

// Where a robot starts each episode: standing on the floor (every robot's own spawn height), or
// at the height of its body's origin in the original's model files, where Safety Gym spawned it:
// the same for the Point and the two-wheel car, 0.2 m lower for the rover, which then starts
// with its wheels in the floor and is thrown up (docs/ENVIRONMENTS.md, ambiguity 1).
enum class Spawn { kStanding, kModelOrigin };

// "standing" or "model-origin"; throws cmbrl::Error naming the text and the choices.
Spawn ParseSpawn(const std::string& name);
std::string SpawnName(Spawn spawn);

}  // namespace cmbrl
