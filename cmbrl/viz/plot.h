// Line plots in panels (PNG and SVG, drawn with Cairo): the learning curves of a sweep report.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace cmbrl {

// A line with a band around it (mean and one standard deviation, say).
struct PlotSeries {
  std::string label;
  std::vector<double> x, y, band;  // band: half-width at each x (empty: no band)
  bool dashed = false;             // drawn dashed, in the legend too
  std::string colour_of;           // the label whose colour it takes (empty: its own)
};

struct PlotPanel {
  std::string title;
  std::string x_label, y_label;
  std::vector<PlotSeries> series;
  // The least value the plotted quantity can take (0 for counts): bands stop there, so that a
  // standard deviation wider than the mean does not draw negative counts.
  double y_floor = -std::numeric_limits<double>::infinity();
};

struct PlotOptions {
  int panel_width_px = 520;
  int panel_height_px = 360;
  int columns = 2;
};

// Where each panel's plotting area landed, in pixels (for checks).
struct PanelArea {
  double x, y, width, height;
};

// Draws the panels in a grid with one shared legend and writes `png_path` and `svg_path` (either
// may be empty to skip it). Series are coloured by label (or by colour_of), the same label the
// same colour in every panel. Throws cmbrl::Error when a file cannot be written or a series' vectors differ in
// length. Thread-safe (no shared state).
std::vector<PanelArea> WritePlots(const std::vector<PlotPanel>& panels, const std::string& png_path,
                                  const std::string& svg_path, const PlotOptions& options = {});

}  // namespace cmbrl
