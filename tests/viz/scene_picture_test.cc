#include "cmbrl/viz/scene_picture.h"

#include <cairo.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "cmbrl/core/check.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

struct Rgb {
  int r, g, b;
};

Rgb PixelRgb(cairo_surface_t* surface, Vec2 pixel) {
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  const uint32_t value = *reinterpret_cast<const uint32_t*>(
      data + static_cast<int>(pixel.y) * stride + 4 * static_cast<int>(pixel.x));
  return {static_cast<int>((value >> 16) & 0xff), static_cast<int>((value >> 8) & 0xff),
          static_cast<int>(value & 0xff)};
}

// Colour of a world point in a written picture.
Rgb PixelAt(cairo_surface_t* surface, const PictureGeometry& g, Vec2 world) {
  return PixelRgb(surface, g.PixelOf(world));
}

SceneState Scene() {
  SceneState scene;
  scene.robot_name = "point";
  scene.robot_radius = 0.15;
  scene.robot = {{-1.0, -1.0}, 0.0};
  scene.goal = {1.0, 1.0};
  scene.hazards = {{0.0, 0.0}};
  scene.vases = {{{1.0, -1.0}, 0.3}};
  scene.goal_radius = 0.3;
  scene.hazard_radius = 0.2;
  scene.vase_half_size = 0.1;
  scene.placement = {-1.5, -1.5, 1.5, 1.5};
  return scene;
}

TEST(ScenePictureTest, DrawsEachObjectWhereItIs) {
  const std::string file = testing::TestTempPath("scene_picture_test.png");
  ScenePicture picture{
      Scene(), {{-1.2, -1.2}, {-1.1, -1.1}, {-1.0, -1.0}}, {false, true, false}, {}, "test scene",
      {}};
  const PictureGeometry g = WriteScenePng(picture, file);
  cairo_surface_t* surface = cairo_image_surface_create_from_png(file.c_str());
  ASSERT_EQ(cairo_surface_status(surface), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(surface), 800);
  // The arena is 800 x 800 between a title band and a legend band.
  EXPECT_EQ(cairo_image_surface_get_height(surface), g.height_px);
  EXPECT_GT(g.height_px, 800 + 2 * 40);
  EXPECT_NEAR(g.pixels_per_metre, 800 / 3.8, 1e-9);  // placement 3 m plus 0.4 m each side
  const Rgb goal = PixelAt(surface, g, {1.0, 1.15});
  EXPECT_GT(goal.g, goal.r + 40);  // green
  const Rgb hazard = PixelAt(surface, g, {0.0, 0.1});
  EXPECT_GT(hazard.b, hazard.r + 40);  // blue
  const Rgb vase = PixelAt(surface, g, {1.0, -1.0});
  EXPECT_LT(vase.r, 60);  // teal
  EXPECT_GT(vase.g, 120);
  const Rgb robot = PixelAt(surface, g, {-1.0, -0.95});
  EXPECT_GT(robot.r, 180);  // red
  EXPECT_LT(robot.g, 80);
  const Rgb floor = PixelAt(surface, g, {0.8, -0.2});
  EXPECT_GT(floor.r, 230);  // the placement area is nearly white
  const Rgb outside = PixelAt(surface, g, {1.8, 0.0});
  EXPECT_EQ(outside.r, 255);
  // The legend's first swatch (hazard) is blue; the caption is dark text in the title band.
  const Rgb swatch = PixelRgb(surface, {22, g.arena_top_px + g.arena_size_px + 0.3 * 89});
  EXPECT_GT(swatch.b, swatch.r + 40);
  bool caption_ink = false;
  for (int x = 10; x < 200 && !caption_ink; ++x) {
    for (int y = 2; y < g.arena_top_px - 2 && !caption_ink; ++y) {
      caption_ink = PixelRgb(surface, {double(x), double(y)}).r < 100;
    }
  }
  EXPECT_TRUE(caption_ink);
  cairo_surface_destroy(surface);
  std::filesystem::remove(file);
}

TEST(ScenePictureTest, PredictedPlansStayInsideTheArena) {
  const std::string file = testing::TestTempPath("scene_picture_clip_test.png");
  ScenePicture picture{Scene(), {}, {}, {}, "", {}};
  // An executed plan that runs straight up, far out of the arena through the title band.
  PredictedPath plan;
  plan.points = {{0.5, 0.0}, {0.5, 50.0}};
  plan.chosen = true;
  picture.predictions = {plan};
  const PictureGeometry g = WriteScenePng(picture, file);
  cairo_surface_t* surface = cairo_image_surface_create_from_png(file.c_str());
  ASSERT_EQ(cairo_surface_status(surface), CAIRO_STATUS_SUCCESS);
  const double column = g.PixelOf({0.5, 0.0}).x;
  EXPECT_LT(PixelAt(surface, g, {0.5, 1.7}).r, 100);  // drawn inside the arena (dark)
  for (int y = 0; y < g.arena_top_px - 1; ++y) {      // and never in the title band
    EXPECT_EQ(PixelRgb(surface, {column, double(y)}).r, 255) << "row " << y;
  }
  cairo_surface_destroy(surface);
  std::filesystem::remove(file);
}

TEST(ScenePictureTest, UnwritablePathAndBadSizeAreNamed) {
  ScenePicture picture{Scene(), {}, {}, {}, "", {}};
  EXPECT_THAT(ErrorMessage([&] { WriteScenePng(picture, "/nonexistent-dir/x.png"); }),
              ::testing::HasSubstr("/nonexistent-dir/x.png"));
  EXPECT_THROW(WriteScenePng(picture, "x.png", {10, 0.4}), Error);
}

}  // namespace
}  // namespace cmbrl
