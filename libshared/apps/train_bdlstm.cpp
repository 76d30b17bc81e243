#include "apps/train_bdlstm.h"

#include "io/acap_file.h"
#include "models/common/model_data.h"
#include "models/common/training.h"

namespace df::apps {

void train_bdlstm(const models::BdlstmTrainOptions& opt, const CommonOptions& common) {
  models::check_bdlstm_options(opt);
  const models::TrainingClaims claims =
      models::claim_training_outputs(opt.output, opt.input, common.force, opt.run);
  const io::AcapReader in(opt.input);
  models::BdlstmTrainer trainer(opt, common, in, models::training_features(in, opt.input));
  models::run_trainer(trainer.hooks(), trainer.model(), opt.run, common.force);
}

}  // namespace df::apps
