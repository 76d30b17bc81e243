// train-msae: train the multiscale attention autoencoder on a shape collection (paper 2).
#include <fmt/format.h>

#include "core/error.h"
#include "core/tool.h"
#include "eval/shape_error.h"
#include "models/msae/train.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "train-msae",
      "Train the stacked attention autoencoders of Yang, Gao, Lai, Gao, Xia, 'Multiscale Mesh\n"
      "Deformation Component Analysis with Attention-based Autoencoders' (TVCG 2021) on ACAP\n"
      "features. Level 0 is one autoencoder AE0 (mesh convolution + fully connected C without\n"
      "bias, decoder with the same C, tanh everywhere) with K_z components; with attention each\n"
      "component k of a block gets a child autoencoder at the next level, fed the block's\n"
      "residual X - X^ weighted per vertex by the attention mask AM_k from C (eq. 4-6). Loss per\n"
      "block: 10 MSE + Omega(C) + V(Z), Omega = group sparsity of C outside a geodesic radius d\n"
      "around each component's centre (heat-method distances / the mesh's diameter).\n\n"
      "INPUT: an acap .h5 with /features/normalized (from obj2acap).\n"
      "OUTPUT: an msae-model .h5 (weights, Adam/RNG state, config, template, normalization,\n"
      "split, geodesic distances from the centres, loss log) for recon-msae and\n"
      "extract-components. Split as in the paper: sequences train on every 10th shape (1:9),\n"
      "collections (--split collection) on a random half; or explicit --train/--test lists.");
  tool.with_threads().with_seed(1).with_force().with_stop_requests();
  df::models::MsaeTrainOptions opt;
  int levels = 0;
  bool no_attention = false;
  auto& app = tool.app();
  app.add_option("INPUT", opt.input, "acap .h5 with normalized features")->required();
  app.add_option("-o,--output", opt.output, "Output model (.h5)")->required();
  auto* n = app.add_option_group("Network (paper: two levels, K_z = 10,5, d = 0.4,0.2)");
  n->add_option(
      "--levels", levels,
      "Number of levels (default: as many as --kz has values); more levels than --kz/--d\n"
      "give continue with K_z 5 and half the previous d");
  n->add_option("--kz", opt.net.kz, "Components of each autoencoder, per level (comma-separated)")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->default_str("10,5");
  n->add_option("--d", opt.net.d, "Omega's normalized geodesic radius per level (comma-separated)")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->default_str("0.4,0.2");
  n->add_flag(
      "--no-attention", no_attention,
      "One autoencoder per level on the whole residual, with as many components as the\n"
      "attention tree has there (paper Table 4; --levels 1 --no-attention is the one-level\n"
      "sparse autoencoder of Tan et al.)");
  n->add_option("--latent", opt.net.latent,
                "Codes z = h C^T, bounded by V(Z) at --theta (linear), or z = tanh(h C^T) (tanh: the\n"
                "paper's 'tanh everywhere' taken literally; its codes saturate at +-1 on real meshes\n"
                "and V(Z) never acts; see docs/msae.md)")
      ->default_val(opt.net.latent)
      ->check(CLI::IsMember({"tanh", "linear"}));
  n->add_option("--decoder-fc", opt.net.decoder_fc,
                "The decoder's fully connected layer: y = tanh(z C) (tanh, the paper's 'tanh\n"
                "everywhere') or y = z C (linear, as the convMesh code of Tan et al.)")
      ->default_val(opt.net.decoder_fc)
      ->check(CLI::IsMember({"tanh", "linear"}));
  n->add_option("--decoder-conv", opt.net.decoder_conv,
                "The decoder's mesh convolution uses the encoder's weights transposed, or shared as\n"
                "they are (as the convMesh code)")
      ->default_val(opt.net.decoder_conv)
      ->check(CLI::IsMember({"transposed", "shared"}));
  n->add_option("--init", opt.net.init,
                "Initial weights: glorot (uniform), normal (N(0, 0.02^2), as the convMesh code) or\n"
                "small (C at glorot x 0.01: components no training shape asks for stay near zero\n"
                "instead of projecting unseen shapes onto random directions)")
      ->default_val(opt.net.init)
      ->check(CLI::IsMember({"glorot", "normal", "small"}));
  n->add_option("--centres", opt.net.centres,
                "Where the components' centres start: random (where the initial weights peak; the\n"
                "reconstruction gradient then draws most to the same vertices) or spread (farthest-\n"
                "point sampling: level 0 over the mesh, a child within its parent's radius); then\n"
                "c_k = argmax_i |C_k,i| every iteration, as the paper")
      ->default_val(opt.net.centres)
      ->check(CLI::IsMember({"random", "spread"}));
  n->add_option("--lambda-recon", opt.net.lambda_recon, "Weight of the reconstruction MSE")
      ->default_val(opt.net.lambda_recon);
  n->add_option("--lambda-sparse", opt.net.lambda_sparse, "Weight of Omega(C)")
      ->default_val(opt.net.lambda_sparse);
  n->add_option("--theta", opt.net.theta,
                "V(Z)'s bound on the codes (tanh codes stay below 1: inactive)")
      ->default_val(opt.net.theta);
  auto* g = app.add_option_group("Training");
  g->add_option("--iterations", opt.training.iterations,
                "Training iterations (batches); the paper's 10,000 epochs are a GPU budget")
      ->default_val(opt.training.iterations);
  g->add_option("--batch", opt.training.batch, "Shapes per iteration, drawn with replacement")
      ->default_val(opt.training.batch);
  g->add_option("--lr", opt.training.lr, "Adam learning rate (betas 0.9/0.999)")
      ->default_val(opt.training.lr);
  g->add_option("--lr-decay", opt.training.lr_decay,
                "Exponential decay: lr x DECAY^(iteration / --lr-decay-steps)")
      ->default_val(opt.training.lr_decay);
  g->add_option("--lr-decay-steps", opt.training.lr_decay_steps, "Iterations per factor --lr-decay")
      ->default_val(opt.training.lr_decay_steps);
  g->add_flag(
      "--separate", opt.training.separate,
      "Train level by level (iterations divided equally; earlier levels frozen) instead of\n"
      "jointly (paper Table 4)");
  g->add_option("--separate-rate", opt.training.separate_rate,
                "With --separate: each level's new Adam starts at --lr (restart) or at the rate the\n"
                "schedule has reached when the level starts (continue: the rate joint training has\n"
                "there, so that joint and separate differ in strategy only)")
      ->default_val(opt.training.separate_rate)
      ->check(CLI::IsMember({"restart", "continue"}));
  g->add_option("--split", opt.training.split,
                "sequence: every --every-th shape of each sequence trains, the rest is held out;\n"
                "collection: a random --train-fraction trains (placed by --seed)")
      ->default_val(opt.training.split)
      ->check(CLI::IsMember({"sequence", "collection"}));
  g->add_option("--every", opt.training.every, "sequence split: train on every N-th shape")
      ->default_val(opt.training.every);
  g->add_option("--train-fraction", opt.training.train_fraction,
                "collection split: fraction trained on")
      ->default_val(opt.training.train_fraction);
  g->add_option(
      "--train", opt.train_list,
      "Train on the shapes of this list (frame names of /frames/names or indices, one per line)");
  g->add_option("--test", opt.test_list,
                "Hold out the shapes of this list (default: every shape not trained on)");
  g->add_option(
       "--validation-fraction", opt.training.validation_fraction,
       "This fraction of the held-out shapes (drawn by --seed) validates instead of testing; its\n"
       "error is logged at every loss line (features, and E_rms x 1000 of positions as\n"
       "eval-metrics measures it). Choose iteration counts and options on it, never on\n"
       "the test shapes")
      ->default_val(opt.training.validation_fraction);
  df::models::add_training_run_options(*g, opt.run);
  tool.footer(
      "Examples:\n"
      "  train-msae bumps.h5 -o bumps-msae.h5\n"
      "  train-msae --split collection --iterations 3000 lion.h5 -o lion-msae.h5\n"
      "  train-msae --levels 1 --kz 50 --no-attention pcow.h5 -o pcow-tan.h5   # one-level AE\n"
      "  train-msae --levels 3 pcow.h5 -o pcow-3.h5                            # K_z 10,5,5\n"
      "  train-msae --resume --checkpoint-every 200 pcow.h5 -o m.h5            # after a kill");
  return tool.run(argc, argv, [&] {
    if (levels < 0) throw df::UsageError("--levels must be positive");
    if (levels > 0) {
      if (app.count("--kz") && static_cast<int>(opt.net.kz.size()) != levels)
        throw df::UsageError(
            fmt::format("--kz has {} values for {} levels", opt.net.kz.size(), levels));
      if (app.count("--d") && static_cast<int>(opt.net.d.size()) != levels)
        throw df::UsageError(
            fmt::format("--d has {} values for {} levels", opt.net.d.size(), levels));
      while (static_cast<int>(opt.net.kz.size()) < levels) opt.net.kz.push_back(5);
      while (static_cast<int>(opt.net.d.size()) < levels) opt.net.d.push_back(opt.net.d.back() / 2);
      opt.net.kz.resize(static_cast<std::size_t>(levels));
      opt.net.d.resize(static_cast<std::size_t>(levels));
    } else if (app.count("--kz") && !app.count("--d")) {
      while (opt.net.d.size() < opt.net.kz.size()) opt.net.d.push_back(opt.net.d.back() / 2);
      opt.net.d.resize(opt.net.kz.size());
    }
    opt.net.attention = !no_attention;
    opt.position_error = [](const df::models::MsaeModel& m, const std::vector<std::int64_t>& frames) {
      auto measure = std::make_shared<df::eval::ShapeErms>(m.split.data, frames, m.normalization);
      return df::models::MsaeShapeMeasure(
          [measure](const df::nn::Matrix<float>& normalized) { return (*measure)(normalized); });
    };
    df::models::train_msae(opt, tool.common());
  });
}
