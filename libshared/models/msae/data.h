// The shapes an MSAE model works on, read from an acap file and checked against the model: the
// same template connectivity, the frames of a split part, features in the model's normalization.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "models/common/frame_part.h"
#include "models/msae/model.h"

namespace df::models {

struct MsaeShapes {
  nn::Matrix<float> x;                 ///< [n, 9V] normalized as the model's training data
  std::vector<std::int64_t> frames;    ///< their frame indices in the file
  std::vector<std::string> names;      ///< their frame names
  std::vector<std::string> sequence;   ///< the name of each one's sequence
  std::vector<std::int64_t> offsets;   ///< the file's sequence offsets
  std::vector<std::string> sequences;  ///< the file's sequence names
  std::string history;
};

/// The frames of `part` (train, validation, test: the model's split, which needs the training
/// data file; all: every frame), read through ModelData (models/common/model_data.h: the
/// template check, the features in the model's normalization). InvalidInput also when a split
/// frame lies beyond the file.
MsaeShapes read_msae_shapes(const MsaeModel& m, const std::string& path, FramePart part);

/// Writes reconstructions of `shapes` as an acap file on the model's template: normalized
/// features [n, 9V] and/or positions [n, 3V] (at least one), one sequence per data sequence,
/// /frames/source pairing each with its frame of `data` (for eval-metrics); `method` is recorded
/// as the attribute `method` of /frames/source.
void write_shapes(const std::string& path, const MsaeModel& m, const MsaeShapes& shapes,
                  const nn::Matrix<float>* features, const nn::Matrix<float>* positions,
                  const std::string& data, const std::vector<std::string>& inputs, bool force,
                  const std::string& method);

}  // namespace df::models
