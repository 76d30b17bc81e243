// recon-msae: encode and decode shapes through a trained MSAE (paper 2).
#include "apps/recon_msae.h"
#include "core/choice_option.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "recon-msae",
      "Encode shapes with a trained MSAE model and decode them through its first 1..L levels\n"
      "(the sum of the levels' outputs), for acap2obj, render-mesh and eval-metrics (E_rms,\n"
      "STED, relative squared error: paper 2 Tables 2, 4, 5).\n"
      "\n"
      "MODEL: from train-msae. DATA: an acap .h5 on the model's template; --part train,\n"
      "validation or test take the model's split of the file it was trained on, all takes\n"
      "every frame of DATA (any file on the same template).\n"
      "OUTPUT: an acap .h5 with /features/normalized and /frames/source (the DATA frame each\n"
      "one reconstructs), so that eval-metrics pairs it with DATA.");
  tool.with_force();
  df::apps::MsaeReconOptions opt;
  auto& app = tool.app();
  app.add_option("MODEL", opt.model, "msae-model .h5")->required();
  app.add_option("DATA", opt.data, "acap .h5 with normalized features")->required();
  app.add_option("-o,--output", opt.output, "Output acap file (.h5)")->required();
  df::add_choice(app, "--part", opt.part,
                 "Which shapes: the model's train, validation or test part, or all of DATA");
  app.add_option("--levels", opt.levels, "Decode through the first L levels, or all of them")
      ->transform(
          [](std::string s) { return s == "all" ? std::string("0") : s; })  // 0: every level
      ->default_str("all");
  app.add_option("--fit-codes", opt.fit_codes,
                 "Fit each shape's codes through the decoders in N Adam steps (least squares,\n"
                 "starting from the encoder's codes) instead of encoding: the protocol PCA and\n"
                 "SPLOCS are measured under, and a diagnostic of the encoder (both feature errors\n"
                 "are printed). 0 = the encoder's codes (the paper's protocol)")
      ->default_val(opt.fit_codes);
  app.add_option("--fit-lr", opt.fit_lr, "--fit-codes: Adam's initial rate (decays tenfold)")
      ->default_val(opt.fit_lr);
  tool.footer(
      "Examples:\n"
      "  recon-msae pcow-msae.h5 pcow.h5 -o pcow-recon.h5 && eval-metrics pcow-recon.h5 pcow.h5\n"
      "  recon-msae --levels 1 pcow-msae.h5 pcow.h5 -o pcow-level0.h5   # coarse level only\n"
      "  recon-msae --fit-codes 300 pcow-msae.h5 pcow.h5 -o fitted.h5   # least-squares codes\n"
      "  recon-msae --part all pcow-msae.h5 other-pcow.h5 -o r.h5");
  return tool.run(argc, argv, [&] { df::apps::recon_msae(opt, tool.common()); });
}
