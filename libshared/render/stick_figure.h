// Stick figures: a skeleton pose drawn into a panel of a Canvas through a Camera — bones as
// anti-aliased lines (far bones first; joints named left/right tinted blue/red), joints as dots.
#pragma once

#include "io/skeleton_file.h"
#include "render/camera.h"
#include "render/canvas.h"

namespace df::render {

/// Draws frame t of `s` into the w by h panel whose top-left corner is (x, y).
void draw_stick_figure(Canvas& canvas, const io::SkeletonFile& s, std::size_t t,
                       const Camera& camera, int x, int y, int w, int h, double margin = 0.08);

}  // namespace df::render
