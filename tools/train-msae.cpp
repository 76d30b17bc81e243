// train-msae: train the multiscale attention autoencoder on a shape collection (paper 2).
#include <fmt/format.h>

#include "apps/train_msae.h"
#include "core/error.h"
#include "core/tool.h"
#include "models/msae/settings.h"

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
      "around each component's centre (heat-method distances / the mesh's diameter).\n"
      "\n"
      "INPUT: an acap .h5 with /features/normalized (from obj2acap).\n"
      "OUTPUT: an msae-model .h5 (weights, Adam/RNG state, config, template, normalization,\n"
      "split, geodesic distances from the centres, loss log) for recon-msae and\n"
      "extract-components. Split as in the paper: sequences train on every 10th shape (1:9),\n"
      "collections (--split collection) on a random half; or explicit --train/--test lists.\n"
      "\n"
      "The defaults are not the paper's form (--paper-form): level 0 started from the training\n"
      "shapes' SPLOCS components (--init local) and kept near them (--started-rate 0.01),\n"
      "mean-centred features, Omega as a proximal step, second-level blocks of 50 components\n"
      "and 16 recombined shapes per batch, chosen by their worst case over every shared set\n"
      "(docs/msae.md). A loss line warns when level 0's components collapse (few distinct\n"
      "centres, supports spanning the mesh, a near-constant code).");
  tool.with_seed(1).with_force().with_stop_requests();
  df::models::MsaeTrainOptions opt;
  // The defaults: the best worst case over the shared sets (docs/msae.md); --paper-form restores
  // the paper's form.
  df::models::apply_msae_defaults(opt.net, opt.training);
  int levels = 0;
  auto& app = tool.app();
  app.add_option("INPUT", opt.input, "acap .h5 with normalized features")->required();
  app.add_option("-o,--output", opt.output, "Output model (.h5)")->required();
  auto* n = app.add_option_group("Network (paper: two levels, K_z = 10,5, d = 0.4,0.2)");
  n->add_option(
      "--levels", levels,
      "Number of levels (default: as many as --kz has values); more levels than --kz/--d\n"
      "give continue with K_z 5 and half the previous d");
  df::models::add_settings(*n, bind(df::models::msae_network_settings(), opt.net, opt.training));
  auto* g = app.add_option_group("Training");
  df::models::add_settings(*g, bind(df::models::msae_training_settings(), opt.net, opt.training));
  g->add_option(
      "--train", opt.train_list,
      "Train on the shapes of this list (frame names of /frames/names or indices, one per line)");
  g->add_option("--test", opt.test_list,
                "Hold out the shapes of this list (default: every shape not trained on)");
  bool paper_form = false;
  g->add_flag("--paper-form", paper_form,
              "The paper's exact form: --init glorot --kz 10,5 --support soft\n"
              "--no-centre-features --synthetic 0 --started-rate 1, every other setting at the\n"
              "paper's value too (options given explicitly still win). The defaults differ in\n"
              "those six, chosen by their worst case over the shared sets' validation shapes\n"
              "(docs/msae.md)");
  df::models::add_training_run_options(*g, opt.run);
  tool.footer(
      "Examples:\n"
      "  train-msae bumps.h5 -o bumps-msae.h5\n"
      "  train-msae --paper-form bumps.h5 -o bumps-paper.h5   # K_z 10,5, soft Omega, uncentred\n"
      "  train-msae --split collection --iterations 3000 lion.h5 -o lion-msae.h5\n"
      "  train-msae --levels 1 --kz 50 --no-attention pcow.h5 -o pcow-tan.h5   # one-level AE\n"
      "  train-msae --levels 3 pcow.h5 -o pcow-3.h5                            # K_z 10,5,5\n"
      "  train-msae --resume --checkpoint-every 200 pcow.h5 -o m.h5            # after a kill");
  return tool.run(argc, argv, [&] {
    if (paper_form) {  // options given explicitly still win
      df::models::MsaeConfig paper_net;
      df::models::MsaeTraining paper_training;
      df::models::take_settings_not_given(
          view(df::models::msae_settings(), paper_net, paper_training),
          bind(df::models::msae_settings(), opt.net, opt.training), app);
    }
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
    df::apps::train_msae(opt, tool.common());
  });
}
