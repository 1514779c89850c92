#include "cmbrl/viz/plot.h"

#include <cairo.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/temp_path.h"

namespace cmbrl {
namespace {

using ::testing::HasSubstr;
using testing::TestTempPath;

// A PNG read once, its pixels as 0xAARRGGBB.
class PngImage {
 public:
  explicit PngImage(const std::string& png)
      : surface_(cairo_image_surface_create_from_png(png.c_str())) {
    EXPECT_EQ(cairo_surface_status(surface_), CAIRO_STATUS_SUCCESS);
    cairo_surface_flush(surface_);
  }
  ~PngImage() { cairo_surface_destroy(surface_); }
  PngImage(const PngImage&) = delete;
  PngImage& operator=(const PngImage&) = delete;

  int width() const { return cairo_image_surface_get_width(surface_); }
  std::uint32_t Pixel(double x, double y) const {
    const unsigned char* data = cairo_image_surface_get_data(surface_);
    const int stride = cairo_image_surface_get_stride(surface_);
    return *reinterpret_cast<const std::uint32_t*>(data + static_cast<int>(y) * stride +
                                                   static_cast<int>(x) * 4);
  }

 private:
  cairo_surface_t* surface_;
};

// Two panels side by side, each with a method's curve and its band and the original's curve
// dashed in the same colour: a valid PNG and SVG, each panel framed.
TEST(PlotTest, PlotsAreValidPngAndSvgWithOnePanelPerTask) {
  std::vector<PlotPanel> panels;
  for (const std::string task : {"PointGoal1", "CarGoal2"}) {
    PlotPanel panel{task, "agent steps", "EpCost", {}};
    for (const std::string method : {"rce", "cem"}) {
      PlotSeries series;
      series.label = method;
      series.x = {100, 200, 300, 400};
      series.y = {4, 3, method == "rce" ? 1.0 : 2.0, 1};
      series.band = {1, 0.5, 0.5, 0};
      panel.series.push_back(series);
      // The original's curve: dashed, in the colour of ours.
      series.label = method + " (original)";
      series.band.clear();
      series.dashed = true;
      series.colour_of = method;
      panel.series.push_back(series);
    }
    panels.push_back(panel);
  }
  const std::string png = TestTempPath("curves.png");
  const std::string svg = TestTempPath("curves.svg");
  const std::vector<PanelArea> areas = WritePlots(panels, png, svg);
  ASSERT_EQ(areas.size(), 2u);
  EXPECT_GT(areas[1].x, areas[0].x + areas[0].width);  // side by side
  // Each panel's frame is drawn (dark) and its inside is not (white where no line passes).
  const PngImage image(png);
  for (const PanelArea& area : areas) {
    const std::uint32_t frame = image.Pixel(area.x, area.y + area.height / 2);
    EXPECT_LT(frame & 0xff, 0x80u) << "frame of the panel at x " << area.x;
  }
  std::ifstream png_file(png, std::ios::binary);
  char magic[8] = {};
  png_file.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  std::ifstream svg_file(svg);
  const std::string text((std::istreambuf_iterator<char>(svg_file)), {});
  EXPECT_THAT(text, ::testing::StartsWith("<?xml"));
  EXPECT_THAT(text, HasSubstr("<svg"));
  EXPECT_THAT(text, HasSubstr("width=\"1040pt\""));  // two panels of 520
  EXPECT_THAT(text, HasSubstr("stroke-dasharray"));  // the original's curves
  EXPECT_THAT(text, ::testing::EndsWith("</svg>\n"));
}

TEST(PlotTest, ABandStopsAtThePanelsFloor) {
  // A mean of 1 violation with a standard deviation of 3: the band would reach -2, a count no run
  // can have. With the panel's floor at 0 the band stops there and the axis with it, so the mean
  // line sits lower in the panel: at (1 + 0.2) / 4.4 of its height (the axis pads by 5% of the
  // range each way), against (1 + 2.3) / 6.6 without the floor.
  PlotPanel panel{"CarGoal1", "agent steps", "EpCost", {}};
  PlotSeries series;
  series.label = "MPC-random";
  series.x = {0, 1000, 2000, 3000};
  series.y = {1, 1, 1, 1};
  series.band = {3, 3, 3, 3};
  panel.series.push_back(series);
  const std::string png = TestTempPath("floor.png");
  // Height of the mean line above the plotting area's bottom, as a fraction of the area: the row
  // of the column in the middle whose red channel is darkest (the band and the grid are light).
  const auto line_height = [&](const PlotPanel& p) {
    const PanelArea area = WritePlots({p}, png, "").at(0);
    const PngImage image(png);
    double darkest_row = -1;
    std::uint32_t darkest = 256;
    for (double y = area.y + 1; y < area.y + area.height - 1; y += 1) {
      const std::uint32_t red = (image.Pixel(area.x + area.width / 2, y) >> 16) & 0xff;
      if (red < darkest) darkest = red, darkest_row = y;
    }
    return (area.y + area.height - darkest_row) / area.height;
  };
  EXPECT_NEAR(line_height(panel), 3.3 / 6.6, 0.02);
  panel.y_floor = 0;
  EXPECT_NEAR(line_height(panel), 1.2 / 4.4, 0.02);
}

TEST(PlotTest, ALegendTooWideForOneRowWrapsInsideThePicture) {
  // Three methods and the original's three beside them in one 520-pixel panel: one row cannot
  // hold the six entries, so the legend takes more rows and pushes the panel down; nothing is
  // drawn past the picture's right edge.
  PlotPanel panel{"PointGoal1", "environment steps", "EpCost", {}};
  for (const char* name : {"CPO", "TRPO-Lagrangian", "TRPO"}) {
    for (const bool original : {false, true}) {
      PlotSeries series;
      series.label = std::string(name) + (original ? " (original)" : "");
      series.x = {0, 1, 2};
      series.y = {1, 2, 3};
      series.dashed = original;
      series.colour_of = name;
      panel.series.push_back(series);
    }
  }
  const std::string png = TestTempPath("legend.png");
  const std::vector<PanelArea> one_row =
      WritePlots({PlotPanel{"t", "x", "y", {panel.series[0]}}}, png, "");
  const std::vector<PanelArea> wrapped = WritePlots({panel}, png, "");
  ASSERT_EQ(wrapped.size(), 1u);
  EXPECT_GE(wrapped[0].y, one_row[0].y + 24);  // at least one more legend row
  const PngImage image(png);
  const int width = image.width();
  EXPECT_EQ(width, 520);
  for (double y = 2; y < wrapped[0].y - 34; y += 1) {
    for (int x = width - 6; x < width; ++x) {
      EXPECT_EQ(image.Pixel(x, y) & 0xffffff, 0xffffffu) << "legend drawn at the edge, y " << y;
    }
  }
}

}  // namespace
}  // namespace cmbrl
