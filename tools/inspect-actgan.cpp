// inspect-actgan: what a trained ActGAN's frame decoder can reach of held-out poses.
#include "apps/inspect_actgan.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "inspect-actgan",
      "What a trained ActGAN's shared frame decoder x = Dec(h, y) can reach (paper 3; issue\n"
      "71's diagnosis): every pose of INPUT's test part (skel2h5 --test-subjects /\n"
      "--test-fraction; every pose with --all or without a test part) gets the latent code h\n"
      "that brings Dec(h, y) nearest to it (Adam from h = 0, the decoder fixed), and the error\n"
      "is set beside the mean training pose and the nearest training pose of the same class\n"
      "(from another sequence). A decoder that reaches held-out poses no better than the\n"
      "nearest training pose cannot generate poses the training set lacks; one far behind it\n"
      "lacks capacity or pre-training. Errors: RMS in the model's normalized coordinates, and\n"
      "the mean per-joint distance in the data's root-centred units. The direct-pose baseline\n"
      "(--generator pose) has no decoder.\n"
      "\n"
      "OUTPUT: the table on stdout; --json FILE (or -) with the same numbers and per class.");
  tool.with_force();
  df::models::ActganInspectOptions opt;
  auto& app = tool.app();
  app.add_option("MODEL", opt.model, "actgan-model .h5")->required();
  app.add_option("INPUT", opt.input, "skeleton .h5 of the same skeleton (the training data)")
      ->required();
  app.add_flag("--all", opt.all, "Every pose, not only the test part's");
  app.add_option("--subjects", opt.subjects,
                 "The poses of these subjects instead (a validation part, e.g. train-actgan's\n"
                 "--validation-subjects); references from the other subjects outside the test part")
      ->delimiter(',');
  app.add_option("--steps", opt.steps, "Adam steps of the latent fit")->default_val(opt.steps);
  app.add_option("--lr", opt.lr, "Adam's initial rate (decays tenfold over the steps)")
      ->default_val(opt.lr);
  app.add_option("--json", opt.json, "Write the numbers as JSON to FILE (- = stdout)");
  tool.footer(
      "Examples:\n"
      "  inspect-actgan actgan.h5 utk.h5                 # held-out subjects' poses\n"
      "  inspect-actgan actgan.h5 utk.h5 --subjects 9     # a validation subject's poses\n"
      "  inspect-actgan actgan.h5 utk.h5 --json reach.json");
  return tool.run(argc, argv, [&] { df::apps::inspect_actgan(opt, tool.common()); });
}
