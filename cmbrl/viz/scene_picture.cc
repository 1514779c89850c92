#include "cmbrl/viz/scene_picture.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>

#include "cmbrl/core/check.h"
#include "cmbrl/viz/cairo_output.h"

namespace cmbrl {
namespace {

// The world rectangle the picture shows: placement area, path and robot, plus a margin, made
// square so that metres are equal in x and y.
Extents ViewOf(const ScenePicture& picture, double margin) {
  Extents view = picture.scene.placement;
  const auto include = [&view](Vec2 p) {
    view.x_min = std::min(view.x_min, p.x);
    view.x_max = std::max(view.x_max, p.x);
    view.y_min = std::min(view.y_min, p.y);
    view.y_max = std::max(view.y_max, p.y);
  };
  for (const Vec2& p : picture.path) include(p);
  include(picture.scene.robot.position);
  if (picture.scene.has_goal) include(picture.scene.goal);
  for (const Pose2& vase : picture.scene.vases) include(vase.position);
  if (picture.scene.box) include(picture.scene.box->position);
  const double cx = (view.x_min + view.x_max) / 2;
  const double cy = (view.y_min + view.y_max) / 2;
  const double half = std::max(view.x_max - view.x_min, view.y_max - view.y_min) / 2 + margin;
  return {cx - half, cy - half, cx + half, cy + half};
}

void Circle(cairo_t* cr, Vec2 centre, double radius) {
  cairo_new_sub_path(cr);
  cairo_arc(cr, centre.x, centre.y, radius, 0, 2 * M_PI);
}

void DrawPlacementArea(cairo_t* cr, const Extents& area, double pixel) {
  cairo_rectangle(cr, area.x_min, area.y_min, area.x_max - area.x_min, area.y_max - area.y_min);
  cairo_set_source_rgb(cr, 0.95, 0.95, 0.93);
  cairo_fill_preserve(cr);
  const double dash = 6 * pixel;
  cairo_set_dash(cr, &dash, 1, 0);
  cairo_set_line_width(cr, 1.5 * pixel);
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0);
}

// Button's, Push's and Circle's objects: the ring and its walls, pillars, buttons (a wrong one
// ringed in red while pressing it costs), gremlins and the box.
void DrawFamilyObjects(cairo_t* cr, const SceneState& scene, double pixel) {
  if (scene.circle_radius > 0.0) {
    cairo_set_source_rgba(cr, 0.1, 0.6, 0.2, 0.9);
    cairo_set_line_width(cr, 3 * pixel);
    Circle(cr, {0.0, 0.0}, scene.circle_radius);
    cairo_stroke(cr);
  }
  cairo_set_source_rgba(cr, 0.9, 0.1, 0.1, 0.8);
  cairo_set_line_width(cr, 3 * pixel);
  for (int i = 0; i < scene.num_walls; ++i) {
    const double at = (i % 2 == 0 ? 1.0 : -1.0) * scene.wall_locate;
    if (i < 2) {
      cairo_move_to(cr, at, -10.0);
      cairo_line_to(cr, at, 10.0);
    } else {
      cairo_move_to(cr, -10.0, at);
      cairo_line_to(cr, 10.0, at);
    }
  }
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0.35, 0.35, 0.55);
  for (const Vec2& pillar : scene.pillars) Circle(cr, pillar, scene.pillar_radius);
  cairo_fill(cr);
  for (size_t i = 0; i < scene.buttons.size(); ++i) {
    cairo_set_source_rgb(cr, 1.0, 0.5, 0.0);
    Circle(cr, scene.buttons[i], scene.button_radius);
    cairo_fill(cr);
    if (scene.buttons_active && static_cast<int>(i) != scene.goal_button) {
      cairo_set_source_rgb(cr, 0.8, 0.0, 0.0);
      cairo_set_line_width(cr, 2 * pixel);
      Circle(cr, scene.buttons[i], scene.button_radius);
      cairo_stroke(cr);
    }
  }
  const auto box = [cr](const Pose2& pose, double half) {
    cairo_save(cr);
    cairo_translate(cr, pose.position.x, pose.position.y);
    cairo_rotate(cr, pose.yaw);
    cairo_rectangle(cr, -half, -half, 2 * half, 2 * half);
    cairo_restore(cr);
  };
  for (const Pose2& gremlin : scene.gremlins) box(gremlin, scene.gremlin_half_size);
  cairo_set_source_rgb(cr, 0.5, 0.0, 1.0);
  cairo_fill(cr);
  if (scene.box) {
    box(*scene.box, scene.box_half_size);
    cairo_set_source_rgb(cr, 0.85, 0.7, 0.0);
    cairo_fill(cr);
  }
}

void DrawPath(cairo_t* cr, const ScenePicture& picture, double pixel) {
  const std::vector<Vec2>& path = picture.path;
  if (path.empty()) return;
  cairo_set_line_width(cr, 2 * pixel);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_source_rgba(cr, 0.45, 0.1, 0.1, 0.8);
  cairo_move_to(cr, path[0].x, path[0].y);
  for (const Vec2& p : path) cairo_line_to(cr, p.x, p.y);
  cairo_stroke(cr);
  // Steps that violated a constraint, as orange dots.
  if (picture.path_violations.size() == path.size()) {
    cairo_set_source_rgb(cr, 1.0, 0.5, 0.0);
    for (size_t i = 0; i < path.size(); ++i) {
      if (picture.path_violations[i]) Circle(cr, path[i], 4 * pixel);
    }
    cairo_fill(cr);
  }
  // Start: a hollow black ring.
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 2 * pixel);
  Circle(cr, path[0], 6 * pixel);
  cairo_stroke(cr);
}

// Feasible predictions in green, infeasible in red, the executed plan bold and dark.
void DrawPredictions(cairo_t* cr, const std::vector<PredictedPath>& predictions, double pixel) {
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (const bool chosen : {false, true}) {
    for (const PredictedPath& path : predictions) {
      if (path.chosen != chosen || path.points.size() < 2) continue;
      if (chosen) {
        cairo_set_source_rgba(cr, 0.1, 0.1, 0.1, 0.9);
        cairo_set_line_width(cr, 2.5 * pixel);
      } else if (path.feasible) {
        cairo_set_source_rgba(cr, 0.0, 0.6, 0.2, 0.35);
        cairo_set_line_width(cr, 1.0 * pixel);
      } else {
        cairo_set_source_rgba(cr, 0.9, 0.1, 0.1, 0.35);
        cairo_set_line_width(cr, 1.0 * pixel);
      }
      cairo_move_to(cr, path.points[0].x, path.points[0].y);
      for (const Vec2& p : path.points) cairo_line_to(cr, p.x, p.y);
      cairo_stroke(cr);
    }
  }
}

void DrawRobot(cairo_t* cr, const SceneState& scene, double pixel) {
  const Vec2 p = scene.robot.position;
  const double r = scene.robot_radius;
  cairo_save(cr);
  cairo_translate(cr, p.x, p.y);
  cairo_rotate(cr, scene.robot.yaw);
  if (scene.robot_name == "point") {
    Circle(cr, {0, 0}, 0.1);
  } else if (scene.robot_name == "rover") {
    cairo_rectangle(cr, -0.2, -0.1, 0.4, 0.2);
  } else {
    cairo_rectangle(cr, -0.1, -0.1, 0.2, 0.2);
  }
  cairo_set_source_rgb(cr, 0.85, 0.1, 0.1);
  cairo_fill(cr);
  // Heading: +x for the point and the rover, -y for the stock car (facts A6).
  const double heading = scene.robot_name == "car" ? -M_PI / 2 : 0.0;
  cairo_rotate(cr, heading);
  cairo_set_source_rgb(cr, 0.3, 0, 0);
  cairo_set_line_width(cr, 3 * pixel);
  cairo_move_to(cr, 0, 0);
  cairo_line_to(cr, r, 0);
  cairo_stroke(cr);
  cairo_restore(cr);
}

void DrawCaption(cairo_t* cr, const std::string& caption, int width, double band) {
  if (caption.empty()) return;
  cairo_save(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, std::max(10.0, width / 50.0));
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, caption.c_str(), &extents);
  cairo_move_to(cr, width / 80.0, band / 2 - extents.y_bearing / 2);
  cairo_show_text(cr, caption.c_str());
  cairo_restore(cr);
}

// A one-metre scale bar in the arena's lower left corner, labelled; in pixels.
void DrawScaleBar(cairo_t* cr, const PictureGeometry& g) {
  const double x = 20;
  const double y = g.arena_top_px + g.arena_size_px - 22;
  cairo_save(cr);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_set_line_width(cr, 3);
  cairo_move_to(cr, x, y);
  cairo_line_to(cr, x + g.pixels_per_metre, y);
  for (const double end : {x, x + g.pixels_per_metre}) {
    cairo_move_to(cr, end, y - 5);
    cairo_line_to(cr, end, y + 5);
  }
  cairo_stroke(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 13);
  cairo_move_to(cr, x + g.pixels_per_metre / 2 - 10, y - 8);
  cairo_show_text(cr, "1 m");
  cairo_restore(cr);
}

// One legend entry: a swatch drawn by `swatch` in a 20-pixel box at (x, y), then the label.
// Returns the x where the next entry starts.
double LegendEntry(cairo_t* cr, double x, double y, const char* label,
                   const std::function<void(double cx, double cy)>& swatch) {
  cairo_save(cr);
  cairo_new_path(cr);  // no segment from the previous label's end
  swatch(x + 10, y);
  cairo_restore(cr);
  cairo_new_path(cr);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, label, &extents);
  cairo_move_to(cr, x + 24, y - extents.y_bearing / 2);
  cairo_show_text(cr, label);
  return x + 24 + extents.x_advance + 18;
}

// Every mark of the picture, in two rows under the arena, in the colours the arena uses: the
// scene's objects (the Goal tasks' hazard, vase and goal; Button's, Push's and Circle's own) and
// the history's marks.
void DrawLegend(cairo_t* cr, const SceneState& scene, const PictureGeometry& g, double band) {
  cairo_save(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, std::max(10.0, g.width_px / 62.0));
  const double row1 = g.arena_top_px + g.arena_size_px + band * 0.3;
  const double row2 = g.arena_top_px + g.arena_size_px + band * 0.72;
  const auto disc = [cr](double r, double g_, double b, double a) {
    return [=](double cx, double cy) {
      cairo_set_source_rgba(cr, r, g_, b, a);
      cairo_arc(cr, cx, cy, 8, 0, 2 * M_PI);
      cairo_fill(cr);
    };
  };
  const auto line = [cr](double r, double g_, double b, double a, double width) {
    return [=](double cx, double cy) {
      cairo_set_source_rgba(cr, r, g_, b, a);
      cairo_set_line_width(cr, width);
      cairo_move_to(cr, cx - 10, cy);
      cairo_line_to(cr, cx + 10, cy);
      cairo_stroke(cr);
    };
  };
  const auto square = [cr](double r, double g_, double b, double a) {
    return [=](double cx, double cy) {
      cairo_set_source_rgba(cr, r, g_, b, a);
      cairo_rectangle(cr, cx - 6, cy - 6, 12, 12);
      cairo_fill(cr);
    };
  };
  const bool goal_task =
      scene.buttons.empty() && !scene.box && scene.circle_radius == 0.0;
  using Swatch = std::function<void(double, double)>;
  std::vector<std::pair<std::string, Swatch>> rows[2];
  std::vector<std::pair<std::string, Swatch>>& objects = rows[0];
  if (goal_task || !scene.hazards.empty()) {
    objects.push_back({"hazard", disc(0.2, 0.35, 1.0, 0.45)});
  }
  if (goal_task) objects.push_back({"vase", square(0.0, 0.65, 0.65, 1.0)});
  if (!scene.buttons.empty()) objects.push_back({"button", disc(1.0, 0.5, 0.0, 1.0)});
  if (!scene.gremlins.empty()) objects.push_back({"gremlin", square(0.5, 0.0, 1.0, 1.0)});
  if (!scene.pillars.empty()) objects.push_back({"pillar", disc(0.35, 0.35, 0.55, 1.0)});
  if (scene.box) objects.push_back({"box", square(0.85, 0.7, 0.0, 1.0)});
  if (scene.circle_radius > 0.0) objects.push_back({"ring", line(0.1, 0.6, 0.2, 0.9, 3)});
  if (scene.num_walls > 0) objects.push_back({"wall", line(0.9, 0.1, 0.1, 0.8, 3)});
  if (scene.has_goal) {
    objects.push_back({scene.buttons.empty() ? "goal" : "goal button", disc(0.1, 0.8, 0.2, 0.5)});
    objects.push_back({"reached goal", disc(0.1, 0.8, 0.2, 0.18)});
  }
  objects.push_back({"robot", disc(0.85, 0.1, 0.1, 1.0)});
  objects.push_back({"start", [cr](double cx, double cy) {
                       cairo_set_source_rgb(cr, 0, 0, 0);
                       cairo_set_line_width(cr, 2);
                       cairo_arc(cr, cx, cy, 6, 0, 2 * M_PI);
                       cairo_stroke(cr);
                     }});
  rows[1] = {{"path", line(0.45, 0.1, 0.1, 0.8, 2)},
             {"violating step", disc(1.0, 0.5, 0.0, 1.0)},
             {"feasible plan", line(0.0, 0.6, 0.2, 0.6, 1.5)},
             {"infeasible plan", line(0.9, 0.1, 0.1, 0.6, 1.5)},
             {"executed plan", line(0.1, 0.1, 0.1, 0.9, 2.5)}};
  // A row too wide for the picture gets a smaller font (each entry keeps its 42-pixel swatch and
  // gap), so that every entry shows.
  const double font = std::max(10.0, g.width_px / 62.0);
  double scale = 1.0;
  for (const auto& row : rows) {
    double text = 0.0, fixed = 12.0;
    for (const auto& [label, swatch] : row) {
      cairo_text_extents_t extents;
      cairo_text_extents(cr, label.c_str(), &extents);
      text += extents.x_advance;
      fixed += 42.0;
    }
    if (fixed + text > g.width_px) scale = std::min(scale, (g.width_px - fixed) / text);
  }
  cairo_set_font_size(cr, font * std::max(scale, 0.3));
  const double heights[2] = {row1, row2};
  for (int r = 0; r < 2; ++r) {
    double x = 12;
    for (const auto& [label, swatch] : rows[r]) x = LegendEntry(cr, x, heights[r], label.c_str(), swatch);
  }
  cairo_restore(cr);
}

}  // namespace

Vec2 PictureGeometry::PixelOf(Vec2 world) const {
  return {(world.x - view.x_min) * pixels_per_metre,
          arena_top_px + arena_size_px - (world.y - view.y_min) * pixels_per_metre};
}

namespace {

// Draws the picture on a new image surface; fills `g`.
CairoSurface DrawScenePicture(const ScenePicture& picture, const ScenePictureOptions& options,
                              PictureGeometry& g) {
  Require(options.size_px >= 64 && options.size_px <= 8192,
          "picture size_px is {}: expected 64 to 8192 pixels", options.size_px);
  const SceneState& scene = picture.scene;
  const int size = options.size_px;
  const double title_band = std::round(size / 18.0);
  const double legend_band = std::round(size / 9.0);
  g.width_px = size;
  g.height_px = static_cast<int>(title_band + size + legend_band);
  g.arena_top_px = title_band;
  g.arena_size_px = size;
  g.view = ViewOf(picture, options.margin_m);
  g.pixels_per_metre = size / (g.view.x_max - g.view.x_min);
  CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, g.width_px, g.height_px));
  CairoContext context(cairo_create(surface.get()));
  cairo_t* cr = context.get();

  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);

  // The arena: world coordinates (metres, y up), everything clipped to it.
  cairo_save(cr);
  cairo_rectangle(cr, 0, title_band, size, size);
  cairo_clip(cr);
  const Extents& view = g.view;
  const double scale = g.pixels_per_metre;
  const double pixel = 1.0 / scale;
  cairo_translate(cr, 0, title_band + size);
  cairo_scale(cr, scale, -scale);
  cairo_translate(cr, -view.x_min, -view.y_min);

  DrawPlacementArea(cr, scene.placement, pixel);

  cairo_set_source_rgba(cr, 0.2, 0.35, 1.0, 0.45);
  for (const Vec2& hazard : scene.hazards) Circle(cr, hazard, scene.hazard_radius);
  cairo_fill(cr);

  DrawFamilyObjects(cr, scene, pixel);

  cairo_set_source_rgba(cr, 0.1, 0.8, 0.2, 0.18);
  for (const Vec2& goal : picture.reached_goals) Circle(cr, goal, scene.goal_radius);
  cairo_fill(cr);
  if (scene.has_goal) {
    cairo_set_source_rgba(cr, 0.1, 0.8, 0.2, 0.5);
    Circle(cr, scene.goal, scene.goal_radius);
    cairo_fill(cr);
  }

  for (const Pose2& vase : scene.vases) {
    cairo_save(cr);
    cairo_translate(cr, vase.position.x, vase.position.y);
    cairo_rotate(cr, vase.yaw);
    const double h = scene.vase_half_size;
    cairo_rectangle(cr, -h, -h, 2 * h, 2 * h);
    cairo_restore(cr);
  }
  cairo_set_source_rgb(cr, 0.0, 0.65, 0.65);
  cairo_fill(cr);

  DrawPredictions(cr, picture.predictions, pixel);
  DrawPath(cr, picture, pixel);
  DrawRobot(cr, scene, pixel);
  cairo_restore(cr);

  // Frame of the arena, then the bands (device pixels).
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, 0.5, title_band + 0.5, size - 1, size - 1);
  cairo_stroke(cr);
  DrawScaleBar(cr, g);
  DrawCaption(cr, picture.caption, size, title_band);
  DrawLegend(cr, scene, g, legend_band);

  cairo_surface_flush(surface.get());
  return surface;
}

}  // namespace

PictureGeometry WriteScenePng(const ScenePicture& picture, const std::string& path,
                              const ScenePictureOptions& options) {
  PictureGeometry g;
  const CairoSurface surface = DrawScenePicture(picture, options, g);
  WriteSurfacePng(surface.get(), path);
  return g;
}

RgbImage DrawScenePictureRgb(const ScenePicture& picture, const ScenePictureOptions& options) {
  PictureGeometry g;
  const CairoSurface surface = DrawScenePicture(picture, options, g);
  RgbImage image;
  image.geometry = g;
  image.pixels.resize(static_cast<size_t>(g.width_px) * g.height_px * 3);
  // ARGB32 is one native-endian 32-bit word a pixel, premultiplied; the white background makes
  // every pixel opaque, so the colour channels are the colours.
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  std::uint8_t* out = image.pixels.data();
  for (int y = 0; y < g.height_px; ++y) {
    const auto* row = reinterpret_cast<const std::uint32_t*>(data + static_cast<size_t>(y) * stride);
    for (int x = 0; x < g.width_px; ++x) {
      *out++ = static_cast<std::uint8_t>(row[x] >> 16);
      *out++ = static_cast<std::uint8_t>(row[x] >> 8);
      *out++ = static_cast<std::uint8_t>(row[x]);
    }
  }
  return image;
}

}  // namespace cmbrl
