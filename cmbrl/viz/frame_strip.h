// An episode as the environment drew it (Env::Frame): its pictures side by side under a caption,
// as one PNG. For environments that draw themselves (a Python one in rgb_array mode), where the
// Goal world's arena picture (scene_picture.h) has nothing to show.
#pragma once

#include <string>
#include <vector>

#include "cmbrl/env/env.h"

namespace cmbrl {

// Writes `frames` left to right, each scaled to the same height (at most 320 pixels), under
// `caption`. Throws cmbrl::Error for no frames, a frame whose bytes do not match its size, or a
// file that cannot be written (naming it). Thread-safe.
void WriteFrameStripPng(const std::vector<RgbFrame>& frames, const std::string& caption,
                        const std::string& path);

}  // namespace cmbrl
