#include "apps/train_msae.h"

#include <memory>

#include "core/error.h"
#include "eval/shape_error.h"
#include "io/acap_file.h"
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
  if (!in.has_normalized())
    throw InvalidInput("has no /features/normalized; run obj2acap on the meshes first", opt.input);
  models::MsaeTrainer trainer(opt, common, in);
  models::run_trainer(trainer.hooks(), trainer.model(), opt.run, common.force);
}

}  // namespace df::apps
