#include "apps/train_bdlstm.h"

#include "core/error.h"
#include "io/acap_file.h"
#include "models/common/training.h"

namespace df::apps {

void train_bdlstm(const models::BdlstmTrainOptions& opt, const CommonOptions& common) {
  models::check_bdlstm_options(opt);
  const models::TrainingClaims claims =
      models::claim_training_outputs(opt.output, opt.input, common.force, opt.run);
  const io::AcapReader in(opt.input);
  if (!in.has_normalized())
    throw InvalidInput("has no /features/normalized; run obj2acap on the meshes first", opt.input);
  models::BdlstmTrainer trainer(opt, common, in);
  models::run_trainer(trainer.hooks(), trainer.model(), opt.run, common.force);
}

}  // namespace df::apps
