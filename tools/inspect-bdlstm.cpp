// inspect-bdlstm: what a trained BD-LSTM's latent carries (diagnosing training).
#include "apps/inspect_bdlstm.h"
#include "core/choice_option.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "inspect-bdlstm",
      "Diagnose a trained BD-LSTM on the data it was trained on: the training log's first and\n"
      "last rows; the KL of q(z|x) against N(0, I) per latent dimension over frames of the\n"
      "training (or held-out) part — near 0 in every dimension means posterior collapse; and\n"
      "windows of that part predicted from --initial given frames with z = the encoder's mean,\n"
      "z drawn from the prior, and z = 0, beside zero motion: when the prior or zero predict as\n"
      "well as the mean, the LSTM does not use what the encoder sees.\n"
      "\n"
      "INPUT: MODEL (bdlstm-model .h5) DATA (the acap .h5 it was trained on). Output: a report\n"
      "on stdout; --tsv FILE adds the KL per dimension and the error per step for plots.");
  tool.with_seed(0).with_force();
  df::apps::BdlstmInspectOptions opt;
  auto& app = tool.app();
  app.add_option("MODEL", opt.model, "bdlstm-model .h5")->required();
  app.add_option("DATA", opt.data, "acap .h5 the model was trained on")->required();
  app.add_option("--tsv", opt.tsv,
                 "Also write the KL per dimension and the errors per step (gnuplot blocks)");
  df::add_choice(app, "--part", opt.part, "train, validation or test: which frames to probe",
                 {"train", "validation", "test"});
  app.add_option("--initial", opt.initial, "Given frames per probe window")
      ->default_val(opt.initial);
  app.add_option("--length", opt.length, "Predicted steps per probe window")
      ->default_val(opt.length);
  app.add_option("--cases", opt.cases, "Probe windows, evenly spaced over the part")
      ->default_val(opt.cases);
  app.add_option("--max-frames", opt.max_frames, "Frames encoded for the KL per dimension")
      ->default_val(opt.max_frames);
  tool.footer("Example:\n  inspect-bdlstm pcow/model.h5 pcow/data.h5 --tsv pcow/latent.tsv");
  return tool.run(argc, argv, [&] { df::apps::inspect_bdlstm(opt, tool.common()); });
}
