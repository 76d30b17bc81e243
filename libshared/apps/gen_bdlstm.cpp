#include "apps/gen_bdlstm.h"

#include <fmt/format.h>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "io/acap_file.h"

namespace df::apps {
using namespace df::models;
namespace {

void check_options(const BdlstmGenerateOptions& opt) {
  if ((opt.method == GenerateMethod::still || opt.method == GenerateMethod::nearest ||
       opt.method == GenerateMethod::damped) &&
      opt.mode != GenerateMode::predict)
    throw UsageError(fmt::format("--method {} is a prediction reference", name_of(opt.method)));
  if (!(opt.damping >= 0 && opt.damping <= 1))
    throw UsageError("--damping must lie in 0..1 (0: static, 1: linear extrapolation)");
  if (opt.neighbours < 1) throw UsageError("--neighbours must be at least 1");
  if (opt.initial < 1) throw UsageError("--initial must be at least 1");
  if (opt.length < 1 || opt.gap < 1 || opt.samples < 1 || opt.retries < 1)
    throw UsageError("--length, --gap, --samples and --retries must be positive");
  if ((opt.method == GenerateMethod::linear || opt.method == GenerateMethod::damped) &&
      opt.mode == GenerateMode::predict && opt.initial < 2)
    throw UsageError(
        fmt::format("{} extrapolation needs --initial 2 or more (it continues the last two frames)",
                    name_of(opt.method)));
  if (opt.mode == GenerateMode::predict && !opt.keyframes.empty())
    throw UsageError("--keyframes is for --mode complete");
  if (opt.mode == GenerateMode::complete && !opt.from.empty())
    throw UsageError("--from is for --mode predict");
  const auto& frames = opt.mode == GenerateMode::predict ? opt.from : opt.keyframes;
  if (frames.empty() == (opt.test_every == 0))
    throw UsageError(opt.mode == GenerateMode::predict
                         ? "give --from or --test-every, one of them"
                         : "give --keyframes or --test-every, one of them");
  if (opt.stride < 0) throw UsageError("--stride must not be negative");
  if (opt.blend < 0) throw UsageError("--blend must not be negative");
  if (!(opt.state_sigma >= 0)) throw UsageError("--state-sigma must not be negative");
  if (!(opt.threshold >= 0)) throw UsageError("--threshold must not be negative");
}

}  // namespace

void write_generated(const std::vector<GeneratedSequence>& out, const BdlstmGenerateOptions& opt,
                     const BdlstmModel& m, const GenerationData& d, const CommonOptions& common) {
  AtomicOutput dest(opt.output, AtomicOutput::Kind::file, common.force, {opt.model, opt.data});
  {
    io::AcapWriter f(dest.temp_path(), opt.output,
                     {m.history == d.history ? d.history : m.history + "\n" + d.history});
    f.write_template(m.tmpl);
    f.write_normalization(m.normalization);
    std::vector<std::string> names, seqs;
    std::vector<std::int64_t> offsets{0}, source;
    std::vector<std::int32_t> step;
    for (const auto& s : out) {
      seqs.push_back(s.name);
      for (std::size_t t = 0; t < s.frames.size(); ++t) names.push_back(fmt::format("{}", t));
      offsets.push_back(offsets.back() + static_cast<std::int64_t>(s.frames.size()));
      source.insert(source.end(), s.source.begin(), s.source.end());
      step.insert(step.end(), s.step.begin(), s.step.end());
    }
    const auto n = static_cast<std::size_t>(offsets.back()),
               nv = static_cast<std::size_t>(m.tmpl.vertices.rows());
    f.write_frame_names(names);
    f.write_source(source, opt.data);
    f.write_steps(step);
    f.write_sequences(offsets, seqs);
    f.create_normalized(n, nv);
    std::size_t row = 0;
    for (const auto& s : out)
      for (const auto& fr : s.frames) f.write_normalized_rows(row++, 1, fr.data());
    f.close();
  }
  dest.commit();
}

void generate_bdlstm(const BdlstmGenerateOptions& opt, const CommonOptions& common) {
  check_options(opt);
  const OutputClaim claim = claim_output(opt.output, common.force, {opt.model, opt.data});
  BdlstmModel m = load_bdlstm_model(opt.model);
  if (opt.mode == GenerateMode::complete && opt.method == GenerateMethod::bdlstm &&
      m.config.directions == Directions::unidirectional)
    throw UsageError(
        "the model was trained unidirectional; completion needs a bidirectional model");
  const GenerationData d = read_generation_data(opt.data, m);
  const std::int64_t q = opt.stride ? opt.stride : m.training.stride;  // data frames per step
  const std::vector<GenerationCase> cases = plan_cases(opt, m, d, q);

  ChainRunner runner(opt, m, d, q, common.seed);
  std::vector<GeneratedSequence> out;
  Progress progress(opt.mode == GenerateMode::predict ? "predicting" : "completing", cases.size());
  for (const auto& c : cases) {
    for (auto& s : opt.mode == GenerateMode::predict ? runner.predict(c) : runner.complete(c))
      out.push_back(std::move(s));
    progress.advance();
  }
  progress.finish();
  if (runner.unmerged())
    log::warn(
        "{} completion(s) did not merge below --threshold {} after {} attempts (worst relative "
        "difference {:.3g}); the closest pair was used",
        runner.unmerged(), runner.threshold(), opt.retries, runner.worst_merge());
  else if (opt.mode == GenerateMode::complete && opt.method == GenerateMethod::bdlstm)
    log::info("every completion merged (worst relative difference {:.3g})", runner.worst_merge());

  write_generated(out, opt, m, d, common);
  std::size_t frames = 0;
  for (const auto& s : out) frames += s.frames.size();
  log::info("wrote {} sequence(s), {} frames to {}", out.size(), frames, opt.output);
}

}  // namespace df::apps
