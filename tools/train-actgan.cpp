// train-actgan: train the action generator with smooth latent transitions (paper 3).
#include "apps/train_actgan.h"
#include "core/tool.h"

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
      "     BCE + Omega (smoothness of latents, sigma1, and poses, sigma2) + gamma x the\n"
      "     classifier's cross-entropy on real and generated sequences; the pre-trained\n"
      "     decoder learns on (--freeze-decoder: it stays fixed).\n"
      "Adam with betas 0.5 / 0.9 for every network (as the authors' code).\n\n"
      "INPUT: a skeleton .h5 of equal-length clips (skel2h5 --length; its test part is not\n"
      "trained on). OUTPUT: an actgan-model .h5 for gen-actgan (weights, Adam and RNG state,\n"
      "config, classes, skeleton, normalization, loss log).");
  tool.with_threads().with_seed(1).with_force().with_stop_requests();
  df::models::ActganTrainOptions opt;
  std::string smoothness = opt.net.smoothness;
  bool direct = false, no_classifier = false, freeze_decoder = false;
  auto& app = tool.app();
  app.add_option("INPUT", opt.input, "skeleton .h5 of equal-length clips")->required();
  app.add_option("-o,--output", opt.output, "Output model (.h5)")->required();
  auto* n = app.add_option_group("Networks (sizes of the authors' code)");
  n->add_option("--noise", opt.net.noise, "Noise values per step (xi_t)")->default_val(opt.net.noise);
  n->add_option("--latent", opt.net.latent, "Latent frame size (h_t)")->default_val(opt.net.latent);
  n->add_option("--hidden", opt.net.hidden, "LSTM hidden size (generator, discriminator, classifier)")
      ->default_val(opt.net.hidden);
  n->add_option("--fc", opt.net.fc, "Hidden layer of the decoder, the heads and the critic")
      ->default_val(opt.net.fc);
  auto* l = app.add_option_group("Losses (ablations: paper Tables 2, 5, 6)");
  l->add_option("--smoothness", smoothness, "Omega's terms: both, latent, action or none")
      ->default_val(smoothness)
      ->check(CLI::IsMember({"both", "latent", "action", "none"}));
  l->add_option("--sigma1", opt.net.sigma1, "Omega's weight on |h_t - h_{t-1}|^2")->default_val(opt.net.sigma1);
  l->add_option("--sigma2", opt.net.sigma2, "Omega's weight on |x_t - x_{t-1}|^2")->default_val(opt.net.sigma2);
  l->add_option("--gamma", opt.net.gamma, "Weight of the classifier's cross-entropy (cycle loss)")
      ->default_val(opt.net.gamma);
  l->add_flag("--direct-latent", direct, "The LSTM gives h_{t+1} itself, not the residual v_t");
  n->add_option("--step-init", opt.net.step_init,
                "The generator's output layer v_t = FC(o_t) at its Glorot draw or x 0.01 (small:\n"
                "the untrained generator stays where h_1 starts instead of drifting out of the\n"
                "decoder's N(0, I) range)")
      ->default_val(opt.net.step_init)
      ->check(CLI::IsMember({"glorot", "small"}));
  n->add_option("--start", opt.net.start,
                "Where each sequence's latent starts: uniform (h_1 ~ U(-1, 1) per dimension, the\n"
                "authors' code) or normal (h_1 ~ N(0, I), the distribution the decoder was\n"
                "pre-trained on); gen-actgan draws as the model was trained")
      ->default_val(opt.net.start)
      ->check(CLI::IsMember({"uniform", "normal"}));
  n->add_option("--discriminator", opt.net.discriminator,
                "The GAN's discriminator: bilstm (the paper's bidirectional LSTM, binary\n"
                "cross-entropy) or critic (a Wasserstein critic MLP on the whole clip [x_1..x_T, y]\n"
                "with the gradient penalty --gp-lambda, as the pre-training's; fixes the clip length)")
      ->default_val(opt.net.discriminator)
      ->check(CLI::IsMember({"bilstm", "critic"}));
  n->add_option("--disc-input", opt.net.disc_input,
                "What the discriminator sees per frame: frames [x_t, y], or motion [x_t,\n"
                "x_t - x_{t-1}, y] (frames and their differences, as the authors' code)")
      ->default_val(opt.net.disc_input)
      ->check(CLI::IsMember({"frames", "motion"}));
  n->add_option("--disc-pool", opt.net.disc_pool,
                "What the discriminator's head reads: last (the BiLSTM's last forward and backward\n"
                "states) or all (every step's outputs, as the authors' code; fixes the clip length)")
      ->default_val(opt.net.disc_pool)
      ->check(CLI::IsMember({"last", "all"}));
  n->add_option("--generator", opt.net.generator,
                "latent: the paper's generator; pose: the baseline RNN whose LSTM output is the\n"
                "pose itself (no latent transitions, no shared decoder; --pretrain-iterations 0)")
      ->default_val(opt.net.generator)
      ->check(CLI::IsMember({"latent", "pose"}));
  l->add_flag("--no-classifier", no_classifier, "No classifier and no cycle loss");
  l->add_option("--gp-lambda", opt.net.gp_lambda, "WGAN-GP gradient penalty (pre-training; the GAN with --discriminator critic)")->default_val(opt.net.gp_lambda);
  auto* g = app.add_option_group("Training");
  g->add_option("--pretrain-iterations", opt.training.pretrain_iterations, "WGAN-GP iterations of the decoder")
      ->default_val(opt.training.pretrain_iterations);
  g->add_option("--iterations", opt.training.iterations, "GAN iterations after the pre-training")
      ->default_val(opt.training.iterations);
  g->add_option("--batch", opt.training.batch, "Sequences per GAN step")->default_val(opt.training.batch);
  g->add_option("--pretrain-batch", opt.training.pretrain_batch, "Poses per pre-training step")
      ->default_val(opt.training.pretrain_batch);
  g->add_option("--critic-steps", opt.training.critic_steps, "Critic updates per decoder update")
      ->default_val(opt.training.critic_steps);
  g->add_option("--d-steps", opt.training.d_steps, "Discriminator updates per iteration (k)")
      ->default_val(opt.training.d_steps);
  g->add_option("--g-steps", opt.training.g_steps, "Generator + classifier updates per iteration")
      ->default_val(opt.training.g_steps);
  g->add_option("--lr", opt.training.lr, "Adam learning rate of the GAN")->default_val(opt.training.lr);
  g->add_option("--lr-pretrain", opt.training.lr_pretrain, "Adam learning rate of the pre-training")
      ->default_val(opt.training.lr_pretrain);
  g->add_option("--disc-lr", opt.training.disc_lr,
                "Adam learning rate of the GAN's discriminator (0: --lr, as the paper); lower than\n"
                "--lr for a discriminator slower than the generator (two time-scale updates)")
      ->default_val(opt.training.disc_lr);
  g->add_flag("--classifier-only", opt.training.classifier_only,
              "Train only the classifier, on the real clips (the paper's Baseline_T/G; with\n"
              "--pretrain-iterations 0): classify-actions then compares it with the classifier\n"
              "trained inside the GAN");
  g->add_option("--validation-subjects", opt.training.validation_subjects,
                "Hold out these training subjects, comma-separated: their clips are not trained\n"
                "on, and every loss line adds the MMD_avg and MMD_seq of 100 sequences generated\n"
                "per class against them (val_mmd_avg, val_mmd_seq) and the same of their frame\n"
                "differences (val_mmd_motion_avg, val_mmd_motion_seq): where they stop falling is\n"
                "the iteration count to train the final model for, without the test part")
      ->delimiter(',')
      ->allow_extra_args(false);  // one comma-separated word: a positional may follow
  g->add_flag("--freeze-decoder", freeze_decoder,
              "Keep the pre-trained frame decoder fixed in the GAN phase, as the authors' code\n"
              "does (only the LSTM learns paths through its latent space); on validation data\n"
              "the discriminator then wins outright, so by default the decoder learns on");
  g->add_option("--disc-noise", opt.training.disc_noise,
                "Instance noise: sigma of Gaussian noise added to every frame the discriminator\n"
                "sees, real and generated (normalized units; 0: none)")
      ->default_val(opt.training.disc_noise);
  df::models::add_training_run_options(*g, opt.run);
  tool.footer(
      "Examples:\n"
      "  train-actgan actions.h5 -o actgan.h5\n"
      "  train-actgan --pretrain-iterations 500 --iterations 1000 --batch 16 utk.h5 -o utk-actgan.h5\n"
      "  train-actgan --smoothness none actions.h5 -o no-smooth.h5          # paper Table 5\n"
      "  train-actgan --direct-latent actions.h5 -o direct.h5               # paper Table 6\n"
      "  train-actgan --validation-subjects 4 actions.h5 -o val.h5          # choose --iterations\n"
      "  train-actgan --discriminator critic --d-steps 5 actions.h5 -o c.h5 # the pipeline's choice");
  return tool.run(argc, argv, [&] {
    opt.net.smoothness = smoothness;
    opt.net.residual = !direct;
    opt.net.classifier = !no_classifier;
    opt.training.train_decoder = !freeze_decoder;
    opt.training.seed = tool.common().seed;
    df::apps::train_actgan(opt, tool.common());
  });
}
