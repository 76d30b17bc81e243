// acap2obj: ACAP features -> mesh files (one per frame) and/or positions in an acap .h5 file.
// De-normalizes with the stored numbers, rebuilds T = exp(L)·S and solves the reconstruction
// system factored once per template, frames in parallel. SPEC §4 (reconstruction).
#pragma once

#include <string>
#include <vector>

#include "core/common_options.h"

namespace df::convert {

struct Acap2ObjOptions {
  std::string input;   ///< acap .h5 with features
  std::string output;  ///< a directory (mesh files) or NAME.h5 (acap kind: reconstructed positions)
  std::string frames;  ///< "0-9,20,30-" (global frame indices); "" = all
  std::vector<std::string> sequences;  ///< sequence names to keep ("" = all)
  std::string name_pattern;       ///< mesh file names: {name} {index} {sequence}; "" = automatic
  std::string features = "auto";  ///< raw | normalized | auto (raw when present)
  int anchor = 0;
  std::string anchor_positions = "auto";  ///< auto | reference | frames
  /// gradients: the exact deformation-gradient system (ReconstructionSolver::gradients);
  /// edges: the SPEC/paper edge system
  std::string solver = "gradients";
};

/// Parses a frame selection ("0-9,20,30-") over n frames into sorted unique indices.
std::vector<std::size_t> parse_frame_selection(const std::string& spec, std::size_t n);

void acap2obj(const Acap2ObjOptions& opt, const CommonOptions& common);

}  // namespace df::convert
