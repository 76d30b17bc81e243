// train-bdlstm: train the share-weight bidirectional LSTM on mesh sequences (paper 1).
#include "apps/train_bdlstm.h"
#include "core/tool.h"
#include "models/bdlstm/settings.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "train-bdlstm",
      "Train the share-weight bidirectional LSTM of Qiao, Lai, Fu, Gao, 'Synthesizing Mesh\n"
      "Deformation Sequences with Bidirectional LSTM' (TVCG 2020) on ACAP features.\n"
      "Each step encodes a frame with 3 mesh convolutions + FC to a Gaussian latent (KL),\n"
      "advances a 3x128 LSTM and decodes the change dX; X(t+1) = X(t) + dX. Each iteration\n"
      "draws --batch windows of --window frames from the training part of the sequences;\n"
      "a forward chain starts at each window's first frame (LSTM states +0.1) and a\n"
      "backward chain at its last frame (states -0.1), both free-running with the same\n"
      "weights. Loss: L_recon + 0.5 L_bidir + 0.1 (L_KL + sum w^2) (eq. 3-5); by default\n"
      "with remedies that keep the latent alive on new data (KL warm-up, free bits, L_2\n"
      "on the weights at 1/8, a small decoder start, and an encoder that reads each step's\n"
      "motion X_t - X_t-1 beside X_t, --motion-input, trained on windows played at speeds\n"
      "0, 0.5, 1 and 1.5, --speeds; --paper-form for the paper's exact form). A loss line warns "
      "when the latent collapses anyway. --carry adds the motion\n"
      "of the step before (fading with --carry-fade): a prediction starts at the given\n"
      "frames' pace (not a default: docs/bdlstm.md).\n"
      "\n"
      "INPUT: an acap .h5 with /features/normalized (from obj2acap).\n"
      "OUTPUT: a bdlstm-model .h5 (weights, Adam/RNG state, config, template,\n"
      "normalization, train/test split, loss log), for gen-bdlstm. A contiguous --test-fraction\n"
      "of every sequence is held out (not trained on): at its end by default; --test-part\n"
      "random places it by the seed, as the paper does (no window crosses it).");
  tool.with_seed(1).with_force().with_stop_requests();
  df::models::BdlstmTrainOptions opt;
  // The defaults learn on new data; --paper-form restores the paper's exact loss and start.
  df::models::apply_learning_defaults(opt.net, opt.training);
  bool paper_form = false;
  auto& app = tool.app();
  app.add_option("INPUT", opt.input, "acap .h5 with normalized features")->required();
  app.add_option("-o,--output", opt.output, "Output model (.h5)")->required();
  auto* g = app.add_option_group("Training");
  df::models::add_settings(*g, bind(df::models::bdlstm_training_settings(), opt.net, opt.training));
  g->add_flag(
      "--paper-form", paper_form,
      "The paper's exact form: --kl-warmup 0 --kl-free-bits 0 --l2-scope all --l2-weight 1\n"
      "--decoder-init zero --carry 0 --no-motion-input --speeds 1 --stopping-fraction 0\n"
      "--stopping-every 0 (options given explicitly still win). The defaults differ in the\n"
      "first five because on new data the paper's form often learns nothing: the latent\n"
      "collapses to the prior and the model predicts no motion, in the motion input and the\n"
      "speeds because without them the model moves at a pace of its own, and in early\n"
      "stopping because what one capture's frames teach often does not carry to its other\n"
      "frames: the model that predicts its unseen frames best is kept (docs/bdlstm.md)");
  g->add_option("--collapse-threshold", opt.training.collapse_threshold,
                "Warn at a loss line (and at the end; recorded in the model file) when the KL is\n"
                "below this many nats per frame while the reconstruction has not improved by 10%:\n"
                "the latent has collapsed and the model predicts what the prior does")
      ->default_val(opt.training.collapse_threshold);
  df::models::add_training_run_options(*g, opt.run, /*model_is_checkpoint=*/false);
  auto* n = app.add_option_group("Network (ablations: paper Table 2)");
  df::models::add_settings(*n, bind(df::models::bdlstm_network_settings(), opt.net, opt.training));
  tool.footer(
      "Examples:\n"
      "  train-bdlstm pcow.h5 -o pcow-bdlstm.h5\n"
      "  train-bdlstm --paper-form pcow.h5 -o pcow-paper.h5                 # eq. 3-5 as written\n"
      "  train-bdlstm --iterations 600 --window 16 --batch 4 finger.h5 -o finger-model.h5\n"
      "  train-bdlstm --directions unidirectional pcow.h5 -o pcow-uni.h5   # ablation\n"
      "  train-bdlstm --resume --checkpoint-every 100 pcow.h5 -o m.h5       # after a kill");
  return tool.run(argc, argv, [&] {
    if (paper_form) {  // options given explicitly still win
      auto paper = opt;
      df::models::apply_paper_form(paper.net, paper.training);
      df::models::take_settings_not_given(
          view(df::models::bdlstm_settings(), paper.net, paper.training),
          bind(df::models::bdlstm_settings(), opt.net, opt.training), app);
    }
    opt.stopping_by_default = app.count("--stopping-fraction") == 0;
    opt.speeds_by_default = app.count("--speeds") == 0;
    df::apps::train_bdlstm(opt, tool.common());
  });
}
