// gen-actgan: action sequences from a trained ActGAN, for classes or a mixture of classes.
#include "apps/gen_actgan.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "gen-actgan",
      "Generate skeleton action sequences from pure noise with a model of train-actgan: for\n"
      "each --class (default: every class) --count sequences, or --count sequences of one soft\n"
      "mixture of classes (--mix walk:0.5,wave:0.5: the label input y = (p_1, ..., p_C)). Each\n"
      "sequence draws its start h_1 (U(-1, 1) or N(0, I), as the model was trained: train-actgan\n"
      "--start) and its noise from --seed and its index: the same seed gives the same\n"
      "sequences.\n"
      "\n"
      "OUTPUT: a skeleton .h5 in the training data's normalized coordinates (its\n"
      "/normalization copied, so render-mesh and eval-metrics read it like the data), named\n"
      "CLASS~k (or A+B~k for a mixture, labelled by its strongest class); --latents FILE adds\n"
      "the latent trajectories h_t as a table (sequence, frame, h1..hZ; paper Fig. 3).");
  tool.with_seed(0).with_force();
  df::models::ActganGenerateOptions opt;
  auto& app = tool.app();
  app.add_option("MODEL", opt.model, "actgan-model .h5")->required();
  app.add_option("-o,--output", opt.output, "Output skeleton file (.h5)")->required();
  app.add_option("--class", opt.classes, "Class to generate (repeatable or comma-separated)")
      ->delimiter(',');
  app.add_option("--mix", opt.mix,
                 "One mixture of classes, CLASS:WEIGHT,... (weights are normalized)");
  app.add_option("--count", opt.count, "Sequences per class (or of the mixture)")
      ->default_val(opt.count);
  app.add_option("--length", opt.length,
                 "Frames per sequence (default: the training clips' length)")
      ->default_val(opt.length);
  app.add_option("--latents", opt.latents, "Also write the latent trajectories (TSV)");
  tool.footer(
      "Examples:\n"
      "  gen-actgan actgan.h5 --count 100 -o generated.h5\n"
      "  gen-actgan actgan.h5 --class walk --length 120 --count 4 --latents walk-h.tsv -o walk.h5\n"
      "  gen-actgan actgan.h5 --mix walk:0.5,wave:0.5 --count 8 -o mixed.h5");
  return tool.run(argc, argv, [&] { df::apps::gen_actgan(opt, tool.common()); });
}
