#include "cmbrl/viz/frame_strip.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include "cmbrl/core/check.h"
#include "cmbrl/viz/cairo_output.h"

namespace cmbrl {
namespace {

constexpr int kMaxHeight = 320;  // pixels of each frame in the strip
constexpr int kGap = 6;          // pixels between frames
constexpr int kCaptionBand = 28;

// A frame as a Cairo image (32-bit xRGB rows).
CairoSurface SurfaceOf(const RgbFrame& frame) {
  Require(frame.width >= 1 && frame.height >= 1 &&
              frame.rgb.size() == static_cast<size_t>(frame.width) * frame.height * 3,
          "a frame of {} x {} pixels holds {} bytes: expected {}", frame.width, frame.height,
          frame.rgb.size(), static_cast<size_t>(frame.width) * frame.height * 3);
  CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, frame.width, frame.height));
  cairo_surface_flush(surface.get());
  unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  for (int y = 0; y < frame.height; ++y) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<size_t>(y) * stride);
    const std::uint8_t* rgb = frame.rgb.data() + static_cast<size_t>(y) * frame.width * 3;
    for (int x = 0; x < frame.width; ++x) {
      row[x] = (std::uint32_t{rgb[3 * x]} << 16) | (std::uint32_t{rgb[3 * x + 1]} << 8) |
               std::uint32_t{rgb[3 * x + 2]};
    }
  }
  cairo_surface_mark_dirty(surface.get());
  return surface;
}

}  // namespace

void WriteFrameStripPng(const std::vector<RgbFrame>& frames, const std::string& caption,
                        const std::string& path) {
  Require(!frames.empty(), "no frames to draw into '{}'", path);
  int height = 0;
  for (const RgbFrame& frame : frames) height = std::max(height, frame.height);
  height = std::min(height, kMaxHeight);
  std::vector<double> scales;
  int width = 0;
  for (const RgbFrame& frame : frames) {
    scales.push_back(static_cast<double>(height) / std::max(frame.height, 1));
    width += static_cast<int>(std::ceil(frame.width * scales.back())) + kGap;
  }
  width = std::max(width - kGap, 200);
  CairoSurface strip(cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height + kCaptionBand));
  CairoContext cr(cairo_create(strip.get()));
  cairo_set_source_rgb(cr.get(), 0.85, 0.85, 0.85);  // the gaps between frames show
  cairo_paint(cr.get());
  cairo_set_source_rgb(cr.get(), 1, 1, 1);
  cairo_rectangle(cr.get(), 0, 0, width, kCaptionBand);
  cairo_fill(cr.get());
  cairo_select_font_face(cr.get(), "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr.get(), 13);
  cairo_set_source_rgb(cr.get(), 0.1, 0.1, 0.1);
  cairo_move_to(cr.get(), 6, kCaptionBand - 9);
  cairo_show_text(cr.get(), caption.c_str());
  double x = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    const CairoSurface frame = SurfaceOf(frames[k]);
    cairo_save(cr.get());
    cairo_translate(cr.get(), x, kCaptionBand);
    cairo_scale(cr.get(), scales[k], scales[k]);
    cairo_set_source_surface(cr.get(), frame.get(), 0, 0);
    cairo_paint(cr.get());
    cairo_restore(cr.get());
    x += std::ceil(frames[k].width * scales[k]) + kGap;
  }
  cairo_surface_flush(strip.get());
  WriteSurfacePng(strip.get(), path);
}

}  // namespace cmbrl
