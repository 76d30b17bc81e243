// train-bdlstm: train the share-weight bidirectional LSTM on mesh sequences (paper 1).
#include "core/tool.h"
#include "models/bdlstm/train.h"

int main(int argc, char** argv) {
  df::Tool tool("train-bdlstm",
                "Train the share-weight bidirectional LSTM of Qiao, Lai, Fu, Gao, 'Synthesizing Mesh\n"
                "Deformation Sequences with Bidirectional LSTM' (TVCG 2020) on ACAP features.\n"
                "Each step encodes a frame with 3 mesh convolutions + FC to a Gaussian latent (KL),\n"
                "advances a 3x128 LSTM and decodes the change dX; X(t+1) = X(t) + dX. Each iteration\n"
                "draws --batch windows of --window frames from the training part of the sequences;\n"
                "a forward chain starts at each window's first frame (LSTM states +0.1) and a\n"
                "backward chain at its last frame (states -0.1), both free-running with the same\n"
                "weights. Loss: L_recon + 0.5 L_bidir + 0.1 (L_KL + sum w^2) (eq. 3-5); by default\n"
                "with remedies that keep the latent alive on new data (KL warm-up, free bits, L_2\n"
                "on the weights at 1/8, a small decoder start; --paper-form for the paper's exact\n"
                "form). A loss line warns when the latent collapses anyway.\n\n"
                "INPUT: an acap .h5 with /features/normalized (from obj2acap).\n"
                "OUTPUT: a bdlstm-model .h5 (weights, Adam/RNG state, config, template,\n"
                "normalization, train/test split, loss log), for gen-bdlstm. A contiguous --test-fraction\n"
                "of every sequence is held out (not trained on): at its end by default; --test-part\n"
                "random places it by the seed, as the paper does (no window crosses it).");
  tool.with_threads().with_seed(1).with_force().with_stop_requests();
  df::models::BdlstmTrainOptions opt;
  // The defaults learn on new data; --paper-form restores the paper's exact loss and start.
  df::models::apply_learning_defaults(opt.net, opt.training);
  std::string directions = "shared";
  bool no_kl = false, no_l2 = false, paper_form = false;
  auto& app = tool.app();
  app.add_option("INPUT", opt.input, "acap .h5 with normalized features")->required();
  app.add_option("-o,--output", opt.output, "Output model (.h5)")->required();
  auto* g = app.add_option_group("Training");
  g->add_option("--iterations", opt.training.iterations, "Training iterations (paper: 7000)")
      ->default_val(opt.training.iterations);
  g->add_option("--window", opt.training.window, "Frames per training window")->default_val(opt.training.window);
  g->add_option("--batch", opt.training.batch, "Windows per iteration")->default_val(opt.training.batch);
  g->add_option("--stride", opt.training.stride, "Use every STRIDE-th frame (2 for slow motion)")
      ->default_val(opt.training.stride);
  g->add_option("--lr", opt.training.lr, "Adam learning rate (betas 0.9/0.999)")->default_val(opt.training.lr);
  g->add_option("--test-fraction", opt.training.test_fraction,
                "Fraction of every sequence held out as a contiguous test part")
      ->default_val(opt.training.test_fraction);
  g->add_option("--validation-fraction", opt.training.validation_fraction,
                "A validation part of each sequence, this fraction of its frames, carved out of the\n"
                "training frames at a place drawn from --seed; no window crosses it. Choose options and\n"
                "iteration counts on it (gen-bdlstm --part validation), never on the test part")
      ->default_val(opt.training.validation_fraction);
  g->add_option("--test-part", opt.training.test_part, "Where the held-out part lies: end, start, middle, or random (placed by --seed)")
      ->default_val(opt.training.test_part)
      ->check(CLI::IsMember({"end", "start", "middle", "random"}));
  g->add_option("--teacher-frames", opt.training.teacher_frames,
                "Feed each chain u ground-truth frames (u uniform in 1..N per iteration) before\n"
                "it runs free, so the network learns to use gen-bdlstm's --initial frames\n"
                "(1 = the paper: only the seed frame)")
      ->default_val(opt.training.teacher_frames);
  g->add_flag("--paper-form", paper_form,
              "The paper's exact form: --kl-warmup 0 --kl-free-bits 0 --l2-scope all --l2-weight 1\n"
              "--decoder-init zero (options given explicitly still win). The defaults differ in\n"
              "those five because on new data the paper's form often learns nothing: the latent\n"
              "collapses to the prior and the model predicts no motion (docs/bdlstm.md)");
  g->add_option("--kl-warmup", opt.training.kl_warmup,
                "Raise the KL weight linearly from 0 to 1 over N iterations (0 = the paper: 1\n"
                "throughout); counters the latent collapsing to the prior")
      ->default_val(opt.training.kl_warmup);
  g->add_option("--collapse-threshold", opt.training.collapse_threshold,
                "Warn at a loss line (and at the end; recorded in the model file) when the KL is\n"
                "below this many nats per frame while the reconstruction has not improved by 10%:\n"
                "the latent has collapsed and the model predicts what the prior does")
      ->default_val(opt.training.collapse_threshold);
  g->add_option("--kl-free-bits", opt.net.free_bits,
                "Free bits: per step, a latent dimension's KL (mean over the batch) below this many\n"
                "nats is not penalised (0 = the paper); the log's kl column is the penalised value")
      ->default_val(opt.net.free_bits);
  df::models::add_training_run_options(*g, opt.run);
  auto* n = app.add_option_group("Network (ablations: paper Table 2)");
  n->add_option("--directions", directions,
                "shared: one network runs both chains (the paper's BD-LSTM); standard: each\n"
                "direction has its own weights; unidirectional: forward chain only")
      ->default_val(directions)
      ->check(CLI::IsMember({"shared", "standard", "unidirectional"}));
  n->add_flag("--no-kl", no_kl, "Deterministic encoder (z = mean), no KL term");
  n->add_flag("--no-l2", no_l2, "No L2 penalty on the weights");
  n->add_option("--latent", opt.net.latent, "Latent size")->default_val(opt.net.latent);
  n->add_option("--hidden", opt.net.hidden, "LSTM hidden size")->default_val(opt.net.hidden);
  n->add_option("--lstm-layers", opt.net.lstm_layers, "LSTM layers")->default_val(opt.net.lstm_layers);
  n->add_option("--conv-layers", opt.net.conv_layers, "Mesh convolutions in the encoder (and decoder)")
      ->default_val(opt.net.conv_layers);
  n->add_option("--alpha-bidir", opt.net.alpha_bidir, "Weight of L_bidir")->default_val(opt.net.alpha_bidir);
  n->add_option("--alpha-reg", opt.net.alpha_reg, "Weight of L_KL + L_2")->default_val(opt.net.alpha_reg);
  n->add_option("--l2-scope", opt.net.l2_scope,
                "L_2 over all trainable values (the paper's Σw²), the weights only (no biases, so\n"
                "the forget-gate bias keeps its 1), or tf: all values, the LSTM forget-gate biases\n"
                "measured from 1 (TensorFlow's forget_bias is a constant outside the weights)")
      ->default_val(opt.net.l2_scope)
      ->check(CLI::IsMember({"all", "weights", "tf"}));
  n->add_option("--l2-weight", opt.net.l2_weight, "Factor of L_2 inside alpha-reg (L_KL + w L_2)")
      ->default_val(opt.net.l2_weight);
  n->add_option("--decoder-init", opt.net.decoder_init,
                "Last decoder convolution at zero (dX = 0 at first) or small (Glorot x 0.01: the\n"
                "encoder gets a reconstruction gradient from the start)")
      ->default_val(opt.net.decoder_init)
      ->check(CLI::IsMember({"zero", "small"}));
  n->add_option("--init-state", opt.net.init_state, "Initial LSTM state of the forward chain (backward: minus)")
      ->default_val(opt.net.init_state);
  tool.footer("Examples:\n"
              "  train-bdlstm pcow.h5 -o pcow-bdlstm.h5\n"
              "  train-bdlstm --paper-form pcow.h5 -o pcow-paper.h5                 # eq. 3-5 as written\n"
              "  train-bdlstm --iterations 600 --window 16 --batch 4 finger.h5 -o finger-model.h5\n"
              "  train-bdlstm --directions unidirectional pcow.h5 -o pcow-uni.h5   # ablation\n"
              "  train-bdlstm --resume --checkpoint-every 100 pcow.h5 -o m.h5       # after a kill");
  return tool.run(argc, argv, [&] {
    if (paper_form) {
      auto given = opt;
      df::models::apply_paper_form(opt.net, opt.training);
      if (app.count("--kl-warmup")) opt.training.kl_warmup = given.training.kl_warmup;
      if (app.count("--kl-free-bits")) opt.net.free_bits = given.net.free_bits;
      if (app.count("--l2-scope")) opt.net.l2_scope = given.net.l2_scope;
      if (app.count("--l2-weight")) opt.net.l2_weight = given.net.l2_weight;
      if (app.count("--decoder-init")) opt.net.decoder_init = given.net.decoder_init;
    }
    opt.net.directions = df::models::directions_from_name(directions);
    opt.net.kl = !no_kl;
    opt.net.l2 = !no_l2;
    df::models::train_bdlstm(opt, tool.common());
  });
}
