#include "apps/train_msae.h"

#include <memory>

#include "eval/shape_error.h"
#include "io/acap_file.h"
#include "models/common/model_data.h"
#include "models/common/training.h"

namespace df::apps {

void train_msae(models::MsaeTrainOptions opt, const CommonOptions& common) {
  opt.position_error = [](const models::MsaeModel& m, const std::vector<std::int64_t>& frames) {
    auto measure = std::make_shared<eval::ShapeErms>(m.split.data, frames, m.normalization);
    return models::MsaeShapeMeasure(
        [measure](const nn::Matrix<float>& normalized) { return (*measure)(normalized); });
  };
  models::check_msae_options(opt);
  const models::TrainingClaims claims =
      models::claim_training_outputs(opt.output, opt.input, common.force, opt.run);
  const io::AcapReader in(opt.input);
  models::MsaeTrainer trainer(opt, common, in, models::training_features(in, opt.input));
  models::run_trainer(trainer.hooks(), trainer.model(), opt.run, common.force);
}

}  // namespace df::apps
