// classify-actions: the classifier of a trained ActGAN applied to a skeleton file.
#include "apps/classify_actions.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "classify-actions",
      "Classify the sequences of a skeleton file with the classifier an ActGAN model trained\n"
      "alongside its generator (paper 3, Table 2): per class the share of sequences whose most\n"
      "probable class is their own. Real data: the file's test part (skel2h5 --test-subjects /\n"
      "--test-fraction) unless --all; generated data (gen-actgan): every sequence, labelled by\n"
      "the class it was generated for. Poses are brought into the model's coordinates through\n"
      "the stored normalizations. Sequences generated for a mixture of classes (gen-actgan --mix)\n"
      "have no right answer: they are not scored, and their class probabilities are printed.\n"
      "--probabilities prints every sequence's class probabilities.\n"
      "\n"
      "OUTPUT: the table on stdout; --json FILE (or -) with accuracies and probabilities.");
  tool.with_force();
  df::apps::ClassifyOptions opt;
  auto& app = tool.app();
  app.add_option("MODEL", opt.model, "actgan-model .h5")->required();
  app.add_option("INPUT", opt.input, "skeleton .h5 (real or generated)")->required();
  app.add_flag("--all", opt.all, "Every sequence, not only the test part");
  app.add_flag("--probabilities", opt.probabilities, "Print each sequence's class probabilities");
  app.add_option("--json", opt.json,
                 "Write accuracies and probabilities as JSON to FILE (- = stdout)");
  tool.footer(
      "Examples:\n"
      "  classify-actions actgan.h5 utk.h5                 # real test sequences\n"
      "  classify-actions actgan.h5 generated.h5\n"
      "  classify-actions actgan.h5 mixed.h5 --probabilities");
  return tool.run(argc, argv, [&] { df::apps::classify_actions(opt, tool.common()); });
}
