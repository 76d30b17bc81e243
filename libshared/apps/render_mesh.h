// render-mesh: pictures of mesh frames and skeleton poses as PNG, without a display or GPU.
// A picture is a contact sheet: one row per input (or per selected sequence), one column per
// selected frame, one camera fitted to everything shown so rows are comparable, captions, and a
// colour bar when vertices are coloured by a scalar (error against a ground truth, deformation
// magnitude, displacement, or a dataset of the input). Meshes are drawn by a z-buffer rasteriser
// with supersampling; skeletons as stick figures with Cairo; Cairo writes the PNG.
#pragma once

#include <string>
#include <vector>

#include "core/common_options.h"

namespace df::apps {

struct RenderOptions {
  std::vector<std::string> inputs;  ///< acap .h5, mesh directories / @lists / files, skeleton .h5
  /// a .png file, or a pattern with {index} (column) and {frame} (frame of the first row) for
  /// one PNG per selected frame
  std::string output;
  std::string frames;                  ///< "0,5,10-20" of each row (of the --sequence when given)
  int every = 0;                       ///< > 0: every K-th of the selected frames
  std::vector<std::string> sequences;  ///< names or indices; each becomes a row
  std::vector<int> steps;              ///< only frames with these /frames/step (gen-bdlstm output)
  std::string error_vs;                ///< ground truth for --color error
  bool show_truth = false;  ///< first row: the ground-truth frames paired with the others
  /// none | error | deformation | displacement | /dataset/path | auto (error with --error-vs)
  std::string color = "auto";
  std::string colormap = "viridis";
  std::vector<double> range;  ///< {lo, hi}; empty = from the data (0 .. max)
  std::string view = "front", up = "y";
  /// all: the camera fits every row; first: only the first row (others may be clipped, e.g. a
  /// baseline that throws spikes would otherwise shrink the truth to a dot)
  std::string fit = "all";
  int width = 320, height = 320;  ///< one panel
  std::string background = "white";
  std::string base_color = "#b4c3d9";  ///< meshes without a scalar colour
  std::string shading = "smooth";      ///< smooth | flat
  int supersample = 3;
  std::vector<std::string> row_labels, column_labels;
  std::string title;
  /// Vertices marked with dots: a handle file (edit-shape's: the first number of each line) on
  /// every mesh, or "edit": on each input's meshes the handles of its /edit record (edit-shape
  /// outputs; none on the other inputs)
  std::string points;
};

void render_mesh(const RenderOptions& opt, const CommonOptions& common);

}  // namespace df::apps
