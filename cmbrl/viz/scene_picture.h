// Top-down pictures of the Goal arena (PNG, drawn with Cairo). Nothing in the core depends on
// this folder.
#pragma once

#include <cstdint>
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
  int size_px = 800;      // width of the image and height of the arena (pixels)
  double margin_m = 0.4;  // floor shown around the placement area and the path (m)
};

// Where things landed in a written picture: a title band on top, the arena (square, metres equal
// in x and y, y up), a legend band below.
struct PictureGeometry {
  int width_px = 0;
  int height_px = 0;
  double arena_top_px = 0.0;     // the arena's first pixel row
  double arena_size_px = 0.0;    // its width and height
  double pixels_per_metre = 0.0;
  Extents view;                  // the world rectangle the arena shows

  // Pixel (x right, y down) of a world point.
  Vec2 PixelOf(Vec2 world) const;
};

// Draws the picture and writes it as PNG: the caption in its own band, objects, path and the
// planner's predictions clipped to the arena, a labelled one-metre scale bar, and a legend of
// every mark (hazard, vase, goal, reached goal, start, robot, path, violating step, feasible,
// infeasible and executed plans). Throws cmbrl::Error when the file cannot be written.
// Thread-safe (no shared state).
PictureGeometry WriteScenePng(const ScenePicture& picture, const std::string& path,
                              const ScenePictureOptions& options = {});

// The same picture in memory: rows of RGB bytes, top row first (height x width x 3).
struct RgbImage {
  PictureGeometry geometry;
  std::vector<std::uint8_t> pixels;
};
RgbImage DrawScenePictureRgb(const ScenePicture& picture, const ScenePictureOptions& options = {});

}  // namespace cmbrl
