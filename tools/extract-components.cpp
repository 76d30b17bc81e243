// extract-components: the multiscale deformation components of a trained MSAE (paper 2).
#include "apps/msae_components.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "extract-components",
      "Decode every component of every autoencoder of a trained MSAE model: the decoder on\n"
      "the one-hot code scaled to the largest positive or most negative code the training\n"
      "shapes reached (the sign with the larger strength is kept), as the deformation it adds\n"
      "to the block's zero code, applied to the reference: X = X_r + Dec(s e_k) - Dec(0).\n"
      "Also writes each component's centre (argmax_i |C_k,i|), strength (paper eq. 7),\n"
      "AE0's attention masks (eq. 6) and the |cosine| similarity of the level-0 components\n"
      "(paper Fig. 3).\n"
      "\n"
      "MODEL: from train-msae. DATA: the acap file it was trained on (for the code ranges).\n"
      "OUTPUT: a components .h5 for prune-components; --acap also writes the components as an\n"
      "acap file (one sequence per level) for acap2obj and render-mesh --color deformation.");
  tool.with_force();
  df::apps::ExtractOptions opt;
  auto& app = tool.app();
  app.add_option("MODEL", opt.model, "msae-model .h5")->required();
  app.add_option("DATA", opt.data, "the acap .h5 the model was trained on")->required();
  app.add_option("-o,--output", opt.output, "Output components file (.h5)")->required();
  app.add_option("--acap", opt.acap, "Also write every component as a frame of an acap file");
  app.add_option("--report", opt.report,
                 "Also print what the model learned, measured on its validation or test shapes:\n"
                 "per component its centre, how much of its weight lies within Omega's radius,\n"
                 "its decoded support and strength, its code range and its share of the shapes'\n"
                 "reconstruction; per level the distinct centres and the effective rank of the\n"
                 "decoded directions against PCA's")
      ->check(CLI::IsMember({"validation", "test"}));
  tool.footer(
      "Examples:\n"
      "  extract-components bumps-msae.h5 bumps.h5 -o comps.h5\n"
      "  extract-components pcow-msae.h5 pcow.h5 -o comps.h5 --report validation\n"
      "  prune-components comps.h5 -o kept.h5 --acap kept-acap.h5\n"
      "  render-mesh kept-acap.h5 --sequence level0 --color deformation -o level0.png");
  return tool.run(argc, argv, [&] { df::apps::extract_components_tool(opt, tool.common()); });
}
