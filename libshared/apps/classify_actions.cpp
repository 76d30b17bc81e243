#include "apps/classify_actions.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/error.h"
#include "io/skeleton_file.h"
#include "models/actgan/generate.h"

namespace df::apps {
using namespace df::models;

namespace {

// What classify-actions reports: per class of the model, the sequences of that (file) class name
// and how many are recognised; sequences generated for a mixture of classes have no right answer
// and are only counted.
struct ClassScores {
  std::vector<int> total, correct;
  int all_total = 0, all_correct = 0;
  std::size_t mixtures = 0;
  std::vector<std::string> mixture_texts;  ///< the distinct mixtures, in order of appearance
};

ClassScores score_sequences(const ActganModel& m, const io::SkeletonFile& s,
                            const std::vector<std::size_t>& seqs, const nn::Matrix<float>& prob) {
  ClassScores sc;
  sc.total.assign(m.class_names.size(), 0);
  sc.correct.assign(m.class_names.size(), 0);
  for (std::size_t r = 0; r < seqs.size(); ++r) {
    if (s.is_mixture(seqs[r])) {
      ++sc.mixtures;
      const std::string text = s.label_text(seqs[r]);
      if (std::find(sc.mixture_texts.begin(), sc.mixture_texts.end(), text) ==
          sc.mixture_texts.end())
        sc.mixture_texts.push_back(text);
      continue;
    }
    const std::string& name = s.class_names.at(static_cast<std::size_t>(s.labels[seqs[r]]));
    const auto it = std::find(m.class_names.begin(), m.class_names.end(), name);
    if (it == m.class_names.end()) continue;
    const auto c = static_cast<std::size_t>(it - m.class_names.begin());
    ++sc.total[c];
    sc.correct[c] +=
        most_probable(prob, static_cast<Eigen::Index>(r)) == static_cast<Eigen::Index>(c);
  }
  for (std::size_t c = 0; c < m.class_names.size(); ++c)
    sc.all_total += sc.total[c], sc.all_correct += sc.correct[c];
  return sc;
}

std::string sequence_key(const io::SkeletonFile& s, std::size_t q) {
  return s.sequence_names[q].empty() ? std::to_string(q) : s.sequence_names[q];
}

nlohmann::ordered_json classification_json(const ClassifyOptions& opt, const ActganModel& m,
                                           const io::SkeletonFile& s,
                                           const std::vector<std::size_t>& seqs,
                                           const nn::Matrix<float>& prob, const ClassScores& sc) {
  nlohmann::ordered_json js;
  js["model"] = opt.model;
  js["input"] = opt.input;
  js["sequences"] = seqs.size();
  for (std::size_t r = 0; r < seqs.size(); ++r) {
    nlohmann::ordered_json p;
    for (std::size_t c = 0; c < m.class_names.size(); ++c)
      p[m.class_names[c]] = prob(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c));
    js["probabilities"][sequence_key(s, seqs[r])] = p;
    if (s.is_mixture(seqs[r])) js["mixture"][sequence_key(s, seqs[r])] = s.label_text(seqs[r]);
  }
  for (std::size_t c = 0; c < m.class_names.size(); ++c)
    if (sc.total[c])
      js["accuracy"][m.class_names[c]] = {{"sequences", sc.total[c]},
                                          {"correct", sc.correct[c]},
                                          {"accuracy", double(sc.correct[c]) / sc.total[c]}};
  if (sc.all_total) js["overall"] = double(sc.all_correct) / sc.all_total;
  return js;
}

// The table on stdout: accuracies of the scored sequences, then the class probabilities of every
// sequence (--probabilities) or of the mixtures, each with its most probable class.
void print_classification(const ClassifyOptions& opt, const ActganModel& m,
                          const io::SkeletonFile& s, const std::vector<std::size_t>& seqs,
                          const nn::Matrix<float>& prob, const ClassScores& sc, bool test_only) {
  fmt::print("{} classified by {} ({} sequences{})\n", opt.input, opt.model, seqs.size(),
             test_only ? ", the test part" : "");
  if (sc.all_total) {
    fmt::print("{:<16} {:>9} {:>8} {:>9}\n", "class", "sequences", "correct", "accuracy");
    for (std::size_t c = 0; c < m.class_names.size(); ++c)
      if (sc.total[c])
        fmt::print("{:<16} {:>9} {:>8} {:>9.3f}\n", m.class_names[c], sc.total[c], sc.correct[c],
                   double(sc.correct[c]) / sc.total[c]);
    fmt::print("{:<16} {:>9} {:>8} {:>9.3f}\n", "all", sc.all_total, sc.all_correct,
               double(sc.all_correct) / sc.all_total);
  }
  if (sc.mixtures)
    fmt::print(
        "{} sequence{} generated for a mixture of classes ({}): not scored; class probabilities "
        "below\n",
        sc.mixtures, sc.mixtures == 1 ? "" : "s", fmt::join(sc.mixture_texts, "; "));
  if (!opt.probabilities && !sc.mixtures) return;
  fmt::print("\n{:<24}", "sequence");
  for (const auto& c : m.class_names) fmt::print(" {:>9.9}", c);
  fmt::print("  most probable\n");
  for (std::size_t r = 0; r < seqs.size(); ++r) {
    if (!opt.probabilities && !s.is_mixture(seqs[r])) continue;
    fmt::print("{:<24}", sequence_key(s, seqs[r]));
    for (Eigen::Index c = 0; c < prob.cols(); ++c)
      fmt::print(" {:>9.3f}", prob(static_cast<Eigen::Index>(r), c));
    fmt::print(
        "  {}\n",
        m.class_names[static_cast<std::size_t>(most_probable(prob, static_cast<Eigen::Index>(r)))]);
  }
}

}  // namespace

void classify_actions(const ClassifyOptions& opt, const CommonOptions& common) {
  const auto claims = claim_outputs({opt.json}, common.force, {opt.model, opt.input});
  const ActganModel m = load_actgan_model(opt.model);
  if (!m.config.classifier)
    throw InvalidInput("the model was trained without a classifier (--no-classifier)", opt.model);
  const io::SkeletonFile s = io::read_skeleton_file(opt.input);
  const bool test_only = !opt.all && std::count(s.test.begin(), s.test.end(), 1) > 0;
  std::vector<std::size_t> seqs;
  for (std::size_t q = 0; q < s.sequences(); ++q)
    if (!test_only || s.test[q]) seqs.push_back(q);
  const nn::Matrix<float> prob = recognise(m, s, seqs).prob;
  const ClassScores sc = score_sequences(m, s, seqs, prob);
  if (opt.json != "-") print_classification(opt, m, s, seqs, prob, sc, test_only);
  if (opt.json.empty()) return;
  const auto js = classification_json(opt, m, s, seqs, prob, sc);
  if (opt.json == "-") {
    fmt::print("{}\n", js.dump(2));
    return;
  }
  write_text_output(opt.json, js.dump(2) + "\n", common.force, {opt.model, opt.input});
}

}  // namespace df::apps
