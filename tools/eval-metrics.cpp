// eval-metrics: error measures of generated / reconstructed meshes against ground truth.
#include "apps/eval_metrics.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "eval-metrics",
      "Compare PRED with TRUTH and print a table (SPEC section 9):\n"
      "  per-vertex position error  mean distance of corresponding vertices, per frame and\n"
      "                             per future-frame step (BD-LSTM paper, Tables 1-2), in\n"
      "                             mesh units and / TRUTH's bounding-box diagonal;\n"
      "  E_rms                      1000 |A - A'|_F / sqrt(3 N V) with TRUTH scaled into\n"
      "                             the unit ball (MSAE paper, Table 2);\n"
      "  STED                       spatial: per vertex the edge-length-weighted std-dev of\n"
      "                             |l' - l| / l over its --sted-rings neighbourhood, averaged;\n"
      "                             temporal: mean |s' - s| of vertex speeds relative to the\n"
      "                             local edge length (per --sted-dt); combined:\n"
      "                             sqrt(spatial^2 + c^2 temporal^2) (Vasa & Skala 2011);\n"
      "  relative squared error     |X - X'|^2 / |X|^2 of normalized ACAP features per frame,\n"
      "                             max and mean (MSAE paper, eq. 8);\n"
      "  feature change             mean |X_t - X_t+1| / |X_t| between consecutive frames of\n"
      "                             PRED's sequences, per time index (BD-LSTM paper, Fig. 2):\n"
      "                             ~0 means frozen, spikes mean jerks; --change-span K\n"
      "                             compares frames K apart instead (sustained motion grows\n"
      "                             with K, frame-to-frame jitter does not);\n"
      "  localization               PRED a components file (extract-components), TRUTH with\n"
      "                             planted regions (synth-meshseq --kind bumps): per region\n"
      "                             the kept component at its level (coarse 0, fine 1) whose\n"
      "                             support (deformation >= --support-threshold x its max)\n"
      "                             has the largest IoU with the region's disc;\n"
      "  spread of samples          mean vertex distance between the samples NAME~k of one\n"
      "                             case (gen-bdlstm --samples) at the same frame;\n"
      "  MMD_avg, MMD_seq           PRED and TRUTH skeleton files (ActGAN paper, appendix):\n"
      "                             unbiased MMD_u^2, Gaussian kernel exp(-|a-b|^2/(2 s^2)),\n"
      "                             max over s = 1e-4..1e9, of generated vs TRUTH's test\n"
      "                             sequences of each class: per frame index (avg) and of\n"
      "                             whole sequences (seq), averaged over classes; the same\n"
      "                             of frame differences x_t+1 - x_t (motion_avg,\n"
      "                             motion_seq: the paper's two barely change when real\n"
      "                             clips are held still or shuffled in time, these do);\n"
      "                             and the spread (distance to the class's mean sequence);\n"
      "                             --pred-subjects / --truth-subjects measure the data\n"
      "                             against itself (the level a generator could reach);\n"
      "  FID, diversity,            skeleton files with --recogniser MODEL (a classifier\n"
      "  multimodality, accuracy    trained alone on the real training clips:\n"
      "                             train-actgan --classifier-only), in its features (the\n"
      "                             hidden layer its output layer reads), as Action2Motion,\n"
      "                             ACTOR and MDM report them: FID of generated vs real test\n"
      "                             clips; diversity, the mean distance of 200 random pairs;\n"
      "                             multimodality, of 20 pairs within each class; accuracy\n"
      "                             of the recogniser's most probable class — and the same\n"
      "                             of the real test clips (FID: one half vs the other).\n"
      "Frames pair through PRED's /frames/source (gen-bdlstm output) or by index. Positions\n"
      "are reconstructed from features (exact solver) when a file stores none; one\n"
      "translation per connected component is removed before measuring (--align rigid:\n"
      "the best rotation too, Kabsch, as the MSAE paper aligns models before E_rms).\n"
      "\n"
      "INPUT: PRED [TRUTH]: acap .h5 files or mesh directories (or two skeleton files, or\n"
      "a components file and a bumps file); with PRED alone only the\n"
      "feature change is measured. OUTPUT: the table on stdout; --json FILE (or -).");
  tool.with_force();
  df::apps::EvalOptions opt;
  auto& app = tool.app();
  app.add_option("PRED", opt.pred, "Predicted / generated frames")->required();
  app.add_option("TRUTH", opt.truth, "Ground truth on the same template");
  app.add_option("--json", opt.json,
                 "Write every number as JSON to FILE (- = stdout, no table); pipelines read this,\n"
                 "never the table");
  app.add_option(
      "--tsv", opt.tsv,
      "Write two tables for plots to FILE: the error per step after the given frames of a\n"
      "gen-bdlstm prediction (gnuplot: index 'step'), or per frame pair of other files\n"
      "(index 'frame': the frame's number in PRED and in TRUTH), and the feature change per\n"
      "time index (index 'feature_change')");
  app.add_option(
         "--steps", opt.steps,
         "Rows of the table: steps of a prediction, or PRED's frames, e.g. 5,10,15 (default:\n"
         "all, or every 5th)")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option(
         "--support-threshold", opt.support_threshold,
         "Components: a vertex is in a component's support when its deformation reaches this\n"
         "fraction of the component's maximum")
      ->default_val(opt.support_threshold);
  app.add_flag("--all-truth", opt.skeletons.all_truth,
               "Skeleton files: compare with all of TRUTH's sequences, not only its test part");
  app.add_option("--pred-subjects", opt.skeletons.pred_subjects,
                 "Skeleton files: only PRED's sequences of these subjects, e.g. 1,2,3")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option(
         "--truth-subjects", opt.skeletons.truth_subjects,
         "Skeleton files: TRUTH's sequences of these subjects (test part or not) instead of\n"
         "its test part. With both, a file against itself: the score of the real clips")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option(
      "--recogniser", opt.recogniser,
      "Skeleton files: an actgan-model .h5 whose classifier recognises the clips (train\n"
      "one alone on the real training clips: train-actgan --classifier-only; a narrow\n"
      "head, --fc 30 as Action2Motion's, keeps FID's covariances estimable): adds FID,\n"
      "diversity, multimodality and accuracy");
  app.add_option("--change-span", opt.change_span,
                 "Feature change between frames K apart (1 = consecutive)")
      ->default_val(opt.change_span);
  app.add_option(
         "--align", opt.align,
         "Before measuring, move each connected part of PRED onto TRUTH by: translation (the\n"
         "reconstruction's own freedom) or rigid (rotation and translation, Kabsch)")
      ->check(CLI::IsMember({"translation", "rigid"}))
      ->default_val(opt.align);
  app.add_option("--sted-rings", opt.sted_rings, "STED neighbourhood in rings")
      ->default_val(opt.sted_rings);
  app.add_option("--sted-dt", opt.sted_dt, "STED frame interval")->default_val(opt.sted_dt);
  app.add_option("--sted-c", opt.sted_c, "STED weight of the temporal part")
      ->default_val(opt.sted_c);
  tool.footer(
      "Examples:\n"
      "  eval-metrics pred.h5 pcow.h5 --steps 5,10,15\n"
      "  eval-metrics long.h5 --json change.json     # freezing / jerks of a generation\n"
      "  eval-metrics long.h5 --change-span 10       # motion over 10 frames\n"
      "  eval-metrics recon.h5 test.h5 --json -\n"
      "  eval-metrics recon.h5 data.h5 --align rigid  # E_rms as the MSAE paper measures it\n"
      "  eval-metrics gen.h5 clips.h5                 # MMD of generated actions (test part)\n"
      "  eval-metrics gen.h5 clips.h5 --recogniser recogniser.h5  # + FID, diversity, ...\n"
      "  eval-metrics clips.h5 clips.h5 --pred-subjects 1,2,3 --truth-subjects 4\n"
      "                                  # the data's own level: training subjects vs one held "
      "out");
  return tool.run(argc, argv, [&] { df::apps::eval_metrics(opt, tool.common()); });
}
