// inspect-actgan's job: what a trained ActGAN's frame decoder can reach
// (models::decoder_reach), printed as a table or written as JSON.
#pragma once

#include "core/common_options.h"
#include "models/actgan/inspect.h"

namespace df::apps {

/// inspect-actgan: the decoder's reach of the poses `opt` selects, as a table on stdout and, with
/// opt.json, as JSON (to stdout for "-").
void inspect_actgan(const models::ActganInspectOptions& opt, const CommonOptions& common);

}  // namespace df::apps
