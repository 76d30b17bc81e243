// Which frames of a model's split a tool works on (recon-msae --part, gen-bdlstm --part,
// inspect-bdlstm --part, fit-baseline --part); names as core/choice.h. A tool that takes only some
// names its own choices.
#pragma once

#include <span>

#include "core/choice.h"

namespace df::models {

enum class FramePart { train, validation, test, all };
inline constexpr Named<FramePart> kFramePartNames[] = {{"train", FramePart::train},
                                                       {"validation", FramePart::validation},
                                                       {"test", FramePart::test},
                                                       {"all", FramePart::all}};
constexpr std::span<const Named<FramePart>> names_of(FramePart) {
  return kFramePartNames;
}

}  // namespace df::models
