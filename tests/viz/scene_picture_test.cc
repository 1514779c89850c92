#include "cmbrl/viz/scene_picture.h"

#include <cairo.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "cmbrl/core/check.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

struct Rgb {
  int r, g, b;
};

// Colour of a world point in a picture of the scene below: the view is the placement area
// [-1.5, 1.5]^2 plus the 0.4 m margin, 800 pixels wide, y up.
Rgb PixelAt(cairo_surface_t* surface, Vec2 world) {
  const double scale = 800 / 3.8;
  const int px = static_cast<int>((world.x + 1.9) * scale);
  const int py = static_cast<int>(800 - (world.y + 1.9) * scale);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  const uint32_t pixel = *reinterpret_cast<const uint32_t*>(data + py * stride + 4 * px);
  return {static_cast<int>((pixel >> 16) & 0xff), static_cast<int>((pixel >> 8) & 0xff),
          static_cast<int>(pixel & 0xff)};
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
  const std::string file = ::testing::TempDir() + "/scene_picture_test.png";
  ScenePicture picture{
      Scene(), {{-1.2, -1.2}, {-1.1, -1.1}, {-1.0, -1.0}}, {false, true, false}, {}, "test scene",
      {}};
  WriteScenePng(picture, file);
  cairo_surface_t* surface = cairo_image_surface_create_from_png(file.c_str());
  ASSERT_EQ(cairo_surface_status(surface), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(surface), 800);
  EXPECT_EQ(cairo_image_surface_get_height(surface), 800);
  const Rgb goal = PixelAt(surface, {1.0, 1.15});
  EXPECT_GT(goal.g, goal.r + 40);  // green
  const Rgb hazard = PixelAt(surface, {0.0, 0.1});
  EXPECT_GT(hazard.b, hazard.r + 40);  // blue
  const Rgb vase = PixelAt(surface, {1.0, -1.0});
  EXPECT_LT(vase.r, 60);  // teal
  EXPECT_GT(vase.g, 120);
  const Rgb robot = PixelAt(surface, {-1.0, -0.95});
  EXPECT_GT(robot.r, 180);  // red
  EXPECT_LT(robot.g, 80);
  const Rgb floor = PixelAt(surface, {0.8, -0.2});
  EXPECT_GT(floor.r, 230);  // the placement area is nearly white
  const Rgb outside = PixelAt(surface, {1.8, 0.0});
  EXPECT_EQ(outside.r, 255);
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
