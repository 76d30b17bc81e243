// fit-baseline: PCA or SPLOCS fitted on an MSAE model's training shapes, for paper 2's tables.
#include "apps/fit_baseline.h"
#include "core/choice_option.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "fit-baseline",
      "Fit a baseline deformation basis on the training shapes of an MSAE model's split and\n"
      "reconstruct its held-out shapes, for the comparisons of paper 2 (Table 2):\n"
      "  pca     principal components of the normalized ACAP features;\n"
      "  splocs  sparse localized deformation components on vertex positions (Neumann et\n"
      "          al., SIGGRAPH Asia 2013, as in the authors' reference code);\n"
      "  splocs-acap  the same algorithm on the normalized ACAP features (local linear\n"
      "          components in MSAE's own space: what locality alone buys there).\n"
      "Held-out shapes are reconstructed by least squares on the components.\n"
      "\n"
      "MODEL: from train-msae (split, template; --components defaults to its total number of\n"
      "components). DATA: the acap file it was trained on.\n"
      "OUTPUT: an acap .h5 like recon-msae's (pca, splocs-acap: features; splocs: positions), for\n"
      "eval-metrics against DATA.");
  tool.with_force();
  df::apps::BaselineOptions opt;
  auto& app = tool.app();
  app.add_option("MODEL", opt.model, "msae-model .h5 (for its split)")->required();
  app.add_option("DATA", opt.data, "the acap .h5 the model was trained on")->required();
  app.add_option("-o,--output", opt.output, "Output acap file (.h5)")->required();
  df::add_choice(app, "--method", opt.method, "pca, splocs or splocs-acap");
  app.add_option("--components-out", opt.components_out,
                 "Also write the fitted basis as a components file, for edit-shape and (pca,\n"
                 "splocs-acap) prune-components, render-mesh (via --acap of prune-components) and\n"
                 "eval-metrics' localization, as extract-components writes MSAE's: component k is\n"
                 "the reference plus its direction at the training shapes' largest coefficient\n"
                 "(splocs: a displacement of the vertices from the mean shape, space 'positions')");
  app.add_option("--components", opt.components,
                 "Number of components (default: as many as the MSAE model)")
      ->default_str("model's");
  df::add_choice(app, "--part", opt.part,
                 "Which shapes to reconstruct: the model's test, validation or train part",
                 {"train", "validation", "test"});
  auto* s = app.add_option_group("SPLOCS (the reference code's defaults)");
  s->add_option("--splocs-iterations", opt.splocs.iterations, "Outer iterations")
      ->default_val(opt.splocs.iterations);
  s->add_option("--splocs-lambda", opt.splocs.lambda, "Sparsity weight")
      ->default_val(opt.splocs.lambda);
  s->add_option("--splocs-dmin", opt.splocs.d_min,
                "Support map: free up to this normalized geodesic distance")
      ->default_val(opt.splocs.d_min);
  s->add_option("--splocs-dmax", opt.splocs.d_max,
                "Support map: fully penalised from this distance")
      ->default_val(opt.splocs.d_max);
  tool.footer(
      "Examples:\n"
      "  fit-baseline --method pca pcow-msae.h5 pcow.h5 -o pcow-pca.h5\n"
      "  fit-baseline --method splocs pcow-msae.h5 pcow.h5 -o pcow-splocs.h5\n"
      "  eval-metrics pcow-splocs.h5 pcow.h5");
  return tool.run(argc, argv, [&] { df::apps::fit_baseline(opt, tool.common()); });
}
