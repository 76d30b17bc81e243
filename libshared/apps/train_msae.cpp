#include "apps/train_msae.h"

#include <memory>

#include "eval/shape_error.h"

namespace df::apps {

void train_msae(models::MsaeTrainOptions opt, const CommonOptions& common) {
  opt.position_error = [](const models::MsaeModel& m, const std::vector<std::int64_t>& frames) {
    auto measure = std::make_shared<eval::ShapeErms>(m.split.data, frames, m.normalization);
    return models::MsaeShapeMeasure(
        [measure](const nn::Matrix<float>& normalized) { return (*measure)(normalized); });
  };
  models::train_msae(opt, common);
}

}  // namespace df::apps
