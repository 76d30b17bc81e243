// gen-bdlstm's job: a trained BD-LSTM's predictions or completions (models/bdlstm/generate.h)
// of the cases planned from the data, written as an acap file.
#pragma once

#include <vector>

#include "core/common_options.h"
#include "models/bdlstm/generate.h"

namespace df::apps {

/// Writes the sequences as an acap file of normalized features with /frames/source and
/// /frames/step (atomically).
void write_generated(const std::vector<models::GeneratedSequence>& out,
                     const models::BdlstmGenerateOptions& opt, const models::BdlstmModel& m,
                     const models::GenerationData& d, const CommonOptions& common);

/// gen-bdlstm: plans the cases, runs the chains, writes the output.
void generate_bdlstm(const models::BdlstmGenerateOptions& opt, const CommonOptions& common);

}  // namespace df::apps
