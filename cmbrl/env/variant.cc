#include "cmbrl/env/variant.h"

#include "cmbrl/core/check.h"

namespace cmbrl {

std::string VariantName(Variant variant) {
  switch (variant) {
    case Variant::kPaper:
      return "paper";
    case Variant::kStandard:
      return "standard";
    case Variant::kPaperLidar:
      return "paper-lidar";
  }
  return "paper";
}

bool IsPaperWorld(Variant variant) { return variant != Variant::kStandard; }

Spawn ParseSpawn(const std::string& name) {
  if (name == "standing") return Spawn::kStanding;
  if (name == "model-origin") return Spawn::kModelOrigin;
  Fail("spawn '{}': expected standing or model-origin", name);
}

std::string SpawnName(Spawn spawn) {
  return spawn == Spawn::kStanding ? "standing" : "model-origin";
}

Variant ParseVariant(const std::string& name) {
  if (name == "paper") return Variant::kPaper;
  if (name == "standard") return Variant::kStandard;
  if (name == "paper-lidar") return Variant::kPaperLidar;
  Fail(
      "unknown variant '{}': expected 'paper' (the paper's modified tasks), 'standard' "
      "(Safety-Gymnasium's stock tasks) or 'paper-lidar' (the paper's tasks as its model-free "
      "baselines observed them)",
      name);
}

}  // namespace cmbrl
