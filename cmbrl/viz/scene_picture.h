// Top-down pictures of the Goal arena (PNG, drawn with Cairo). Nothing in the core depends on
// this folder.
#pragma once

#include <string>
#include <vector>

#include "cmbrl/env/scene.h"

namespace cmbrl {

// A trajectory the planner predicted, in world coordinates.
struct PredictedPath {
  std::vector<Vec2> points;  // from the robot's position at planning time
  bool feasible = true;      // no ensemble member predicted a violation along it
  bool chosen = false;       // the plan the agent executed (drawn on top, bold)
};

// What one picture shows: the arena as it is at the end, and the history that led there.
struct ScenePicture {
  SceneState scene;
  std::vector<Vec2> path;                  // robot positions, one per agent step, start first
  std::vector<bool> path_violations;       // (path.size()) or empty: cost of the step reaching it
  std::vector<Vec2> reached_goals;         // goals the robot reached, in order
  std::string caption;                     // one line drawn at the top
  std::vector<PredictedPath> predictions;  // planner predictions at chosen steps
};

struct ScenePictureOptions {
  int size_px = 800;      // width and height of the image (pixels)
  double margin_m = 0.4;  // floor shown around the placement area and the path (m)
};

// Draws the picture and writes it as PNG. Throws cmbrl::Error when the file cannot be written.
// Thread-safe (no shared state).
void WriteScenePng(const ScenePicture& picture, const std::string& path,
                   const ScenePictureOptions& options = {});

}  // namespace cmbrl
