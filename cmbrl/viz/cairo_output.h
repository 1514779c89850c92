// Cairo's pictures written through core/files.h: Cairo writing a file itself reports a full disk
// only as "error while writing to output stream"; through memory the error names the cause.
// Also the owning handles of Cairo's surfaces and contexts.
#pragma once

#include <cairo.h>

#include <memory>
#include <string>

#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"

namespace cmbrl {

struct CairoSurfaceDeleter {
  void operator()(cairo_surface_t* surface) const { cairo_surface_destroy(surface); }
};
struct CairoContextDeleter {
  void operator()(cairo_t* context) const { cairo_destroy(context); }
};
using CairoSurface = std::unique_ptr<cairo_surface_t, CairoSurfaceDeleter>;
using CairoContext = std::unique_ptr<cairo_t, CairoContextDeleter>;

// A cairo_write_func_t that appends to the std::string behind `closure`.
inline cairo_status_t AppendToString(void* closure, const unsigned char* data,
                                     unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

// Writes an image surface as a PNG file. Throws cmbrl::Error naming the file and the cause.
inline void WriteSurfacePng(cairo_surface_t* surface, const std::string& path) {
  std::string bytes;
  const cairo_status_t status = cairo_surface_write_to_png_stream(surface, AppendToString, &bytes);
  Require(status == CAIRO_STATUS_SUCCESS, "could not write '{}': {}", path,
          cairo_status_to_string(status));
  WriteFile(path, bytes);
}

}  // namespace cmbrl
