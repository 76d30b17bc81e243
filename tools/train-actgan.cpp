// train-actgan: train the action generator with smooth latent transitions (paper 3).
#include "apps/train_actgan.h"
#include "core/tool.h"
#include "models/actgan/settings.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "train-actgan",
      "Train the human-action generator of Wang, Chang, Wang, Chen, Zhang, Carin, 'Learning\n"
      "Diverse Stochastic Human-Action Generators by Learning Smooth Latent Transitions'\n"
      "(AAAI 2020) on labelled skeleton clips:\n"
      "  1. pre-training (--pretrain-iterations): the shared frame decoder Dec(h, y) as a\n"
      "     conditional WGAN-GP generator of single poses, h ~ N(0, I), against a critic MLP;\n"
      "     --critic-steps critic updates (gradient penalty --gp-lambda) per decoder update;\n"
      "  2. the bi-directional GAN (--iterations, Algorithm 1): an implicit LSTM over (noise,\n"
      "     label) gives latent residuals, h_{t+1} = h_t + v_t, each decoded to a pose; a\n"
      "     bidirectional-LSTM discriminator judges (sequence, label) and a classifier of the\n"
      "     same form labels real and generated sequences; per iteration --d-steps\n"
      "     discriminator updates, then --g-steps updates of generator + classifier on\n"
      "     the adversarial loss + Omega (smoothness of latents, sigma1, and poses, sigma2)\n"
      "     + gamma x the classifier's cross-entropy on real and generated sequences; the\n"
      "     pre-trained decoder learns on (--freeze-decoder: it stays fixed).\n"
      "The defaults are not the paper's form (--paper-form): the discriminator is a Wasserstein\n"
      "critic of whole clips with the gradient penalty, 5 critic steps per iteration, Omega\n"
      "keeps its pose term only and latents start at h_1 ~ N(0, I) — chosen on validation parts\n"
      "(docs/actgan.md).\n"
      "Adam with betas 0.5 / 0.9 for every network (as the authors' code).\n"
      "\n"
      "INPUT: a skeleton .h5 of equal-length clips (skel2h5 --length; its test part is not\n"
      "trained on). OUTPUT: an actgan-model .h5 for gen-actgan (weights, Adam and RNG state,\n"
      "config, classes, skeleton, normalization, loss log).");
  tool.with_seed(1).with_force().with_stop_requests();
  df::models::ActganTrainOptions opt;
  // The defaults: chosen on validation parts (docs/actgan.md); --paper-form
  // restores the paper's discriminator, step count, smoothness and start.
  df::models::apply_learning_defaults(opt.net, opt.training);
  bool paper_form = false;
  auto& app = tool.app();
  app.add_option("INPUT", opt.input, "skeleton .h5 of equal-length clips")->required();
  app.add_option("-o,--output", opt.output, "Output model (.h5)")->required();
  auto* n = app.add_option_group("Networks (sizes of the authors' code)");
  df::models::add_settings(*n, bind(df::models::actgan_network_settings(), opt.net, opt.training));
  auto* l = app.add_option_group("Losses (ablations: paper Tables 2, 5, 6)");
  df::models::add_settings(*l, bind(df::models::actgan_loss_settings(), opt.net, opt.training));
  auto* g = app.add_option_group("Training");
  df::models::add_settings(*g, bind(df::models::actgan_training_settings(), opt.net, opt.training));
  g->add_option("--validation-subjects", opt.training.validation_subjects,
                "Hold out these training subjects, comma-separated: their clips are not trained\n"
                "on, and every loss line adds the MMD_avg and MMD_seq of 100 sequences generated\n"
                "per class against them (val_mmd_avg, val_mmd_seq) and the same of their frame\n"
                "differences (val_mmd_motion_avg, val_mmd_motion_seq): where they stop falling is\n"
                "the iteration count to train the final model for, without the test part")
      ->delimiter(',')
      ->allow_extra_args(false);  // one comma-separated word: a positional may follow
  g->add_flag(
      "--paper-form", paper_form,
      "The paper's form: --discriminator bilstm --d-steps 1 --smoothness both --start uniform\n"
      "(options given explicitly still win). The defaults differ because on validation parts\n"
      "the paper's BiLSTM discriminator moved the sequences away from the data in every\n"
      "setting tried while a Wasserstein critic of whole clips held them at the data's level,\n"
      "Omega's latent term slowed one-arm gestures, and latents starting at N(0, I) scored the\n"
      "best worst case over three validation sets (docs/actgan.md)");
  df::models::add_training_run_options(*g, opt.run);
  tool.footer(
      "Examples:\n"
      "  train-actgan actions.h5 -o actgan.h5\n"
      "  train-actgan --pretrain-iterations 500 --iterations 1000 --batch 16 utk.h5 -o "
      "utk-actgan.h5\n"
      "  train-actgan --smoothness none actions.h5 -o no-smooth.h5          # paper Table 5\n"
      "  train-actgan --direct-latent actions.h5 -o direct.h5               # paper Table 6\n"
      "  train-actgan --validation-subjects 4 actions.h5 -o val.h5          # choose --iterations\n"
      "  train-actgan --paper-form actions.h5 -o paper.h5                   # BiLSTM, both terms");
  return tool.run(argc, argv, [&] {
    if (paper_form) {  // options given explicitly still win
      auto paper = opt;
      df::models::apply_paper_form(paper.net, paper.training);
      df::models::take_settings_not_given(
          view(df::models::actgan_settings(), paper.net, paper.training),
          bind(df::models::actgan_settings(), opt.net, opt.training), app);
    }
    opt.training.seed = tool.common().seed;
    df::apps::train_actgan(opt, tool.common());
  });
}
