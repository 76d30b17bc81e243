#include "apps/train_actgan.h"

#include "core/error.h"
#include "core/rng.h"
#include "eval/skeleton_metrics.h"
#include "io/skeleton_file.h"
#include "models/actgan/generate.h"
#include "models/common/training.h"

namespace df::apps {

using eval::ClassSkeletonMetrics;
using eval::RowMatrixF;

std::vector<double> actgan_validation_mmd(const models::ActganModel& model,
                                          const models::ActionClips& clips, int per_class) {
  const auto classes = static_cast<Eigen::Index>(model.class_names.size());
  const auto fs = static_cast<std::size_t>(clips.pose);
  const auto row = static_cast<Eigen::Index>(static_cast<std::size_t>(clips.length) * fs);
  Rng rng(model.training.seed,
          2);  // the same noise at every evaluation: the curve shows the model, not the draw
  double avg = 0, seq = 0, motion_avg = 0, motion_seq = 0;
  int measured = 0;
  for (Eigen::Index c = 0; c < classes; ++c) {
    std::vector<std::size_t> real;
    for (std::size_t k = 0; k < clips.size(); ++k)
      if (clips.labels[k] == c) real.push_back(k);
    if (real.size() < 2) continue;
    nn::Matrix<float> y = nn::Matrix<float>::Zero(per_class, classes);
    y.col(c).setOnes();
    std::vector<float> poses, latents;
    models::generate_actions(model, y, clips.length, rng, poses, latents);
    const RowMatrixF X = Eigen::Map<const RowMatrixF>(poses.data(), per_class, row);
    RowMatrixF Y(static_cast<Eigen::Index>(real.size()), row);
    for (std::size_t r = 0; r < real.size(); ++r)
      std::copy_n(clips.frame(real[r], 0), static_cast<std::size_t>(row),
                  Y.row(static_cast<Eigen::Index>(r)).data());
    const ClassSkeletonMetrics m = eval::skeleton_class_metrics(X, Y, fs);
    avg += m.mmd_avg;
    seq += m.mmd_seq;
    motion_avg += m.mmd_motion_avg;
    motion_seq += m.mmd_motion_seq;
    ++measured;
  }
  if (measured == 0) throw InvalidInput("no class has 2 validation clips: MMD needs 2 of each");
  return {avg / measured, seq / measured, motion_avg / measured, motion_seq / measured};
}

void train_actgan(models::ActganTrainOptions opt, const CommonOptions& common) {
  opt.validate = [](const models::ActganModel& m, const models::ActionClips& clips) {
    return actgan_validation_mmd(m, clips);
  };
  models::check_actgan_options(opt);
  const models::TrainingClaims claims =
      models::claim_training_outputs(opt.output, opt.input, common.force, opt.run);
  const io::SkeletonFile s = io::read_skeleton_file(opt.input);
  models::ActganTrainer trainer(opt, s);
  models::run_trainer(trainer.hooks(), trainer.model(), opt.run, common.force);
}

}  // namespace df::apps
