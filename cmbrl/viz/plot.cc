#include "cmbrl/viz/plot.h"

#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "cmbrl/core/check.h"
#include "cmbrl/viz/cairo_output.h"

namespace cmbrl {
namespace {

struct Rgb {
  double r, g, b;
};

// How a label is drawn: its colour and whether dashed.
struct Style {
  Rgb colour;
  bool dashed = false;
};

void SetDash(cairo_t* cr, bool dashed) {
  static const double kDash[] = {7.0, 4.0};
  cairo_set_dash(cr, kDash, dashed ? 2 : 0, 0);
}

// Colour-blind-safe colours (Okabe and Ito), in order of first appearance of a label.
const std::vector<Rgb>& Palette() {
  static const std::vector<Rgb> kColours = {{0.0, 0.45, 0.70}, {0.90, 0.62, 0.0},
                                            {0.0, 0.62, 0.45}, {0.80, 0.47, 0.65},
                                            {0.34, 0.71, 0.91}, {0.84, 0.37, 0.0}};
  return kColours;
}

// About five round tick values covering [low, high].
std::vector<double> Ticks(double low, double high) {
  const double span = std::max(high - low, 1e-12);
  const double raw = span / 5;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double factor : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (factor * magnitude >= raw) {
      step = factor * magnitude;
      break;
    }
  }
  std::vector<double> ticks;
  for (double t = std::ceil(low / step) * step; t <= high + step * 1e-9; t += step) {
    ticks.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
  }
  return ticks;
}

std::string TickLabel(double value) {
  if (std::abs(value) >= 1000 && std::fmod(value, 1000) == 0) {
    return fmt::format("{}k", value / 1000);
  }
  return fmt::format("{:g}", value);
}

void Text(cairo_t* cr, const std::string& text, double x, double y, double size, double align_x,
          double align_y, bool vertical = false) {
  cairo_save(cr);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  cairo_translate(cr, x, y);
  if (vertical) cairo_rotate(cr, -M_PI / 2);
  cairo_move_to(cr, -extents.width * align_x - extents.x_bearing,
                -extents.height * align_y - extents.y_bearing);
  cairo_show_text(cr, text.c_str());
  cairo_restore(cr);
}

// Where the legend's entries go: left to right, wrapped onto another row where the next one
// would not fit the picture's width.
struct LegendPlace {
  std::string label;
  double x, y;  // start of the swatch; y is the row's middle
};
struct LegendLayout {
  std::vector<LegendPlace> places;
  double height = 0;
};

constexpr double kLegendFont = 14, kLegendRow = 24, kLegendMargin = 20;
constexpr double kSwatch = 28, kSwatchGap = 6, kEntryGap = 24;

void SelectFont(cairo_t* cr) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
}

LegendLayout LayOutLegend(const std::map<std::string, Style>& styles, double width) {
  cairo_surface_t* scratch = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 1, 1);
  cairo_t* cr = cairo_create(scratch);
  SelectFont(cr);
  cairo_set_font_size(cr, kLegendFont);
  LegendLayout layout;
  double x = kLegendMargin;
  int row = 0;
  for (const auto& entry : styles) {
    cairo_text_extents_t extents;
    cairo_text_extents(cr, entry.first.c_str(), &extents);
    const double entry_width = kSwatch + kSwatchGap + extents.x_advance;
    if (x > kLegendMargin && x + entry_width > width - kLegendMargin / 2) {
      ++row;
      x = kLegendMargin;
    }
    layout.places.push_back({entry.first, x, kLegendRow * (row + 0.5) + 5});
    x += entry_width + kEntryGap;
  }
  cairo_destroy(cr);
  cairo_surface_destroy(scratch);
  layout.height = kLegendRow * (row + 1) + 10;
  return layout;
}

void DrawLegend(cairo_t* cr, const std::map<std::string, Style>& styles,
                const LegendLayout& legend) {
  for (const LegendPlace& place : legend.places) {
    const Style& style = styles.at(place.label);
    cairo_set_source_rgb(cr, style.colour.r, style.colour.g, style.colour.b);
    cairo_set_line_width(cr, 3);
    SetDash(cr, style.dashed);
    cairo_move_to(cr, place.x, place.y);
    cairo_line_to(cr, place.x + kSwatch, place.y);
    cairo_stroke(cr);
    SetDash(cr, false);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    Text(cr, place.label, place.x + kSwatch + kSwatchGap, place.y, kLegendFont, 0, 0.5);
  }
}

// The band's edges at point k (the line itself without a band); the lower stops at the floor.
double BandLow(const PlotSeries& s, size_t k, double floor) {
  return std::max(s.y[k] - (s.band.empty() ? 0.0 : s.band[k]), floor);
}
double BandHigh(const PlotSeries& s, size_t k) {
  return s.y[k] + (s.band.empty() ? 0.0 : s.band[k]);
}

// A panel's data ranges (x from 0 at most, y padded by 5%) and where they land in its area.
struct PanelAxes {
  PanelArea area;
  double x_low, x_high, y_low, y_high;
  double px(double x) const { return area.x + (x - x_low) / (x_high - x_low) * area.width; }
  double py(double y) const {
    return area.y + area.height - (y - y_low) / (y_high - y_low) * area.height;
  }
};

PanelAxes AxesOf(const PlotPanel& panel, const PanelArea& area) {
  double x_low = std::numeric_limits<double>::infinity(), x_high = -x_low;
  double y_low = x_low, y_high = -x_low;
  for (const PlotSeries& s : panel.series) {
    for (size_t k = 0; k < s.x.size(); ++k) {
      x_low = std::min(x_low, s.x[k]);
      x_high = std::max(x_high, s.x[k]);
      y_low = std::min(y_low, BandLow(s, k, panel.y_floor));
      y_high = std::max(y_high, BandHigh(s, k));
    }
  }
  if (!std::isfinite(x_low)) x_low = 0, x_high = 1, y_low = 0, y_high = 1;
  if (x_high <= x_low) x_high = x_low + 1;
  if (y_high <= y_low) y_high = y_low + 1;
  x_low = std::min(x_low, 0.0);
  const double pad = 0.05 * (y_high - y_low);
  return {area, x_low, x_high, y_low - pad, y_high + pad};
}

void DrawGrid(cairo_t* cr, const PanelAxes& a) {
  const PanelArea& area = a.area;
  cairo_set_line_width(cr, 1);
  for (double t : Ticks(a.x_low, a.x_high)) {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, a.px(t), area.y);
    cairo_line_to(cr, a.px(t), area.y + area.height);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
    Text(cr, TickLabel(t), a.px(t), area.y + area.height + 6, 12, 0.5, 0);
  }
  for (double t : Ticks(a.y_low, a.y_high)) {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, area.x, a.py(t));
    cairo_line_to(cr, area.x + area.width, a.py(t));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
    Text(cr, TickLabel(t), area.x - 6, a.py(t), 12, 1, 0.5);
  }
}

// The bands, then the lines, clipped to the plotting area.
void DrawSeries(cairo_t* cr, const PlotPanel& panel, const std::map<std::string, Style>& styles,
                const PanelAxes& a) {
  cairo_save(cr);
  cairo_rectangle(cr, a.area.x, a.area.y, a.area.width, a.area.height);
  cairo_clip(cr);
  for (const PlotSeries& s : panel.series) {
    const Rgb c = styles.at(s.label).colour;
    if (!s.band.empty() && s.x.size() > 1) {
      cairo_move_to(cr, a.px(s.x[0]), a.py(BandHigh(s, 0)));
      for (size_t k = 1; k < s.x.size(); ++k) cairo_line_to(cr, a.px(s.x[k]), a.py(BandHigh(s, k)));
      for (size_t k = s.x.size(); k-- > 0;) {
        cairo_line_to(cr, a.px(s.x[k]), a.py(BandLow(s, k, panel.y_floor)));
      }
      cairo_close_path(cr);
      cairo_set_source_rgba(cr, c.r, c.g, c.b, 0.2);
      cairo_fill(cr);
    }
  }
  for (const PlotSeries& s : panel.series) {
    const Rgb c = styles.at(s.label).colour;
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_set_line_width(cr, 2);
    SetDash(cr, s.dashed);
    for (size_t k = 0; k < s.x.size(); ++k) {
      k == 0 ? cairo_move_to(cr, a.px(s.x[k]), a.py(s.y[k]))
             : cairo_line_to(cr, a.px(s.x[k]), a.py(s.y[k]));
    }
    if (s.x.size() == 1) cairo_rectangle(cr, a.px(s.x[0]) - 2, a.py(s.y[0]) - 2, 4, 4);
    cairo_stroke(cr);
    SetDash(cr, false);
  }
  cairo_restore(cr);
}

std::vector<PanelArea> Draw(cairo_t* cr, const std::vector<PlotPanel>& panels,
                            const PlotOptions& o, const std::map<std::string, Style>& styles,
                            const LegendLayout& legend) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  SelectFont(cr);
  DrawLegend(cr, styles, legend);
  std::vector<PanelArea> areas;
  for (size_t i = 0; i < panels.size(); ++i) {
    const PlotPanel& panel = panels[i];
    const double left = (i % o.columns) * o.panel_width_px;
    const double top = legend.height + (i / o.columns) * o.panel_height_px;
    const PanelArea area{left + 64, top + 34, o.panel_width_px - 84.0, o.panel_height_px - 84.0};
    areas.push_back(area);
    const PanelAxes axes = AxesOf(panel, area);
    DrawGrid(cr, axes);
    DrawSeries(cr, panel, styles, axes);
    // Frame, title and axis labels.
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_set_line_width(cr, 1.2);
    cairo_rectangle(cr, area.x, area.y, area.width, area.height);
    cairo_stroke(cr);
    Text(cr, panel.title, area.x + area.width / 2, top + 16, 16, 0.5, 0.5);
    Text(cr, panel.x_label, area.x + area.width / 2, area.y + area.height + 26, 13, 0.5, 0);
    Text(cr, panel.y_label, left + 14, area.y + area.height / 2, 13, 0.5, 0.5, true);
  }
  return areas;
}

}  // namespace

std::vector<PanelArea> WritePlots(const std::vector<PlotPanel>& panels, const std::string& png_path,
                                  const std::string& svg_path, const PlotOptions& options) {
  Require(!panels.empty(), "nothing to plot: no panels");
  Require(options.columns >= 1, "plot columns is {}: expected at least 1", options.columns);
  // Colours go to colour keys (a series' colour_of, else its label) in order of appearance.
  std::vector<std::string> order;
  std::map<std::string, Style> styles;
  for (const PlotPanel& panel : panels) {
    for (const PlotSeries& s : panel.series) {
      Require(s.x.size() == s.y.size() && (s.band.empty() || s.band.size() == s.x.size()),
              "series '{}' of panel '{}' has {} x, {} y and {} band values", s.label, panel.title,
              s.x.size(), s.y.size(), s.band.size());
      const std::string& key = s.colour_of.empty() ? s.label : s.colour_of;
      if (std::find(order.begin(), order.end(), key) == order.end()) order.push_back(key);
    }
  }
  for (const PlotPanel& panel : panels) {
    for (const PlotSeries& s : panel.series) {
      const std::string& key = s.colour_of.empty() ? s.label : s.colour_of;
      const size_t index = std::find(order.begin(), order.end(), key) - order.begin();
      styles[s.label] = Style{Palette()[index % Palette().size()], s.dashed};
    }
  }
  const int columns = std::min<int>(options.columns, static_cast<int>(panels.size()));
  const int rows = static_cast<int>((panels.size() + columns - 1) / columns);
  const double width = columns * options.panel_width_px;
  const LegendLayout legend = LayOutLegend(styles, width);
  const double height = legend.height + rows * options.panel_height_px;
  PlotOptions o = options;
  o.columns = columns;
  std::vector<PanelArea> areas;
  if (!png_path.empty()) {
    cairo_surface_t* surface = cairo_image_surface_create(
        CAIRO_FORMAT_ARGB32, static_cast<int>(width), static_cast<int>(height));
    cairo_t* cr = cairo_create(surface);
    areas = Draw(cr, panels, o, styles, legend);
    cairo_destroy(cr);
    try {
      WriteSurfacePng(surface, png_path);
    } catch (...) {
      cairo_surface_destroy(surface);
      throw;
    }
    cairo_surface_destroy(surface);
  }
  if (!svg_path.empty()) {
    std::string bytes;
    cairo_surface_t* surface =
        cairo_svg_surface_create_for_stream(AppendToString, &bytes, width, height);
    cairo_t* cr = cairo_create(surface);
    areas = Draw(cr, panels, o, styles, legend);
    cairo_destroy(cr);
    cairo_surface_finish(surface);
    const cairo_status_t status = cairo_surface_status(surface);
    cairo_surface_destroy(surface);
    Require(status == CAIRO_STATUS_SUCCESS, "could not write '{}': {}", svg_path,
            cairo_status_to_string(status));
    WriteFile(svg_path, bytes);
  }
  return areas;
}

}  // namespace cmbrl
