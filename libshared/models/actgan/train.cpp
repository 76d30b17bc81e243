#include "models/actgan/train.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "core/log.h"
#include "io/skeleton_file.h"
#include "models/actgan/settings.h"
#include "models/common/training.h"
#include "nn/ops.h"
#include "nn/train_step.h"

namespace df::models {
namespace {

using Matrix = nn::Matrix<float>;
using Var = nn::Var<float>;
using Bound = nn::Bound<float>;
using Step = nn::StepStore<float>;
using nn::train_step;

}  // namespace

void check_actgan_options(const ActganTrainOptions& opt) {
  const auto& t = opt.training;
  const auto& c = opt.net;
  check_ranges(view(actgan_settings(), c, t));
  if (c.generator == Generator::pose && t.pretrain_iterations > 0)
    throw UsageError(
        "the direct-pose baseline (--generator pose) has no decoder to pre-train: use "
        "--pretrain-iterations 0");
  if (c.generator == Generator::pose && c.step_init != StepInit::glorot)
    throw UsageError(
        "--step-init sets the latent generator's steps v_t: the direct-pose baseline (--generator "
        "pose) has none");
  if (c.generator == Generator::pose && !t.train_decoder)
    throw UsageError(
        "the direct-pose baseline (--generator pose) has no decoder to freeze: leave out "
        "--freeze-decoder");
  if (c.discriminator == Discriminator::critic &&
      (c.disc_input != DiscInput::frames || c.disc_pool != DiscPool::last))
    throw UsageError(
        "--disc-input and --disc-pool shape the BiLSTM discriminator: the critic (--discriminator "
        "critic) reads whole clips");
  if (t.classifier_only && (t.pretrain_iterations > 0 || !c.classifier))
    throw UsageError(
        "--classifier-only trains the classifier alone: use --pretrain-iterations 0, not "
        "--no-classifier");
  opt.run.check();
}

namespace {

void check_resumable(const ActganModel& ck, const ActganModel& want, const std::string& path) {
  require_same_settings(view(actgan_settings(), ck.config, ck.training),
                        view(actgan_settings(), want.config, want.training), path);
  auto differs = [&](const char* what, const auto& a, const auto& b) {
    require_same_setting(what, a, b, path);
  };
  differs("validation-subjects", fmt::format("{}", fmt::join(ck.training.validation_subjects, ",")),
          fmt::format("{}", fmt::join(want.training.validation_subjects, ",")));
  differs("length", ck.length, want.length);
  if (ck.class_names != want.class_names)
    throw InvalidInput("checkpoint was trained on other classes", path);
}

// Random training frames (pre-training): rows of x and their labels.
void draw_frames(const ActionClips& d, int n, Rng& rng, Matrix& x, std::vector<int>& labels) {
  x.resize(n, d.pose);
  labels.resize(static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r) {
    const std::size_t clip = rng.below(d.size());
    const std::size_t t = rng.below(static_cast<std::uint64_t>(d.length));
    x.row(r) = Eigen::Map<const Eigen::RowVectorXf>(d.frame(clip, t), d.pose);
    labels[static_cast<std::size_t>(r)] = d.labels[clip];
  }
}

// The labels of n random training clips (the classes in their training frequencies).
std::vector<int> draw_labels(const ActionClips& d, int n, Rng& rng) {
  std::vector<int> labels(static_cast<std::size_t>(n));
  for (auto& l : labels) l = d.labels[rng.below(d.size())];
  return labels;
}

// Random training clips: frames[t] [n, P] and labels.
void draw_clips(const ActionClips& d, int n, Rng& rng, std::vector<Matrix>& frames,
                std::vector<int>& labels) {
  frames.assign(static_cast<std::size_t>(d.length), Matrix(n, d.pose));
  labels.resize(static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r) {
    const std::size_t clip = rng.below(d.size());
    for (std::size_t t = 0; t < frames.size(); ++t)
      frames[t].row(r) = Eigen::Map<const Eigen::RowVectorXf>(d.frame(clip, t), d.pose);
    labels[static_cast<std::size_t>(r)] = d.labels[clip];
  }
}

std::vector<Var> constants(nn::Tape<float>& t, const std::vector<Matrix>& m) {
  std::vector<Var> v;
  for (const auto& x : m) v.push_back(t.constant(x));
  return v;
}

std::vector<Matrix> values(const std::vector<Var>& v) {
  std::vector<Matrix> m;
  for (const auto& x : v) m.push_back(x.value());
  return m;
}

float mean_value(Var v) {
  return v.value().mean();
}

// n draws of U(0, 1) as a column (the gradient penalty's interpolation weights).
Matrix uniform_column(Eigen::Index n, Rng& rng) {
  Matrix eps(n, 1);
  for (Eigen::Index i = 0; i < n; ++i) eps(i) = static_cast<float>(rng.uniform());
  return eps;
}

// Instance noise (--disc-noise): x_t + sigma N(0, I) per frame, the noise a constant drawn from
// rng; x itself without noise (and nothing drawn) when sigma is 0.
std::vector<Var> with_instance_noise(const std::vector<Var>& x, double sigma, Rng& rng) {
  if (sigma == 0) return x;
  std::vector<Var> out;
  for (const auto& f : x) {
    Matrix n(f.rows(), f.cols());
    for (Eigen::Index i = 0; i < n.size(); ++i)
      n.data()[i] = static_cast<float>(sigma * rng.normal());
    out.push_back(nn::add(f, f.tape->constant(n)));
  }
  return out;
}

}  // namespace

LossTerms actgan_pretrain_iteration(ActganModel& m, const ActionClips& d, nn::Tape<float>& tape) {
  const auto& tr = m.training;
  const int n = tr.pretrain_batch;
  Matrix x, h(n, m.config.latent);
  std::vector<int> labels;
  double critic_loss = 0, wasserstein = 0, gp = 0;
  for (int k = 0; k < tr.critic_steps; ++k) {
    draw_frames(d, n, m.rng, x, labels);
    const Matrix y = one_hot<float>(labels, m.config.classes);
    for (Eigen::Index i = 0; i < h.size(); ++i) h.data()[i] = static_cast<float>(m.rng.normal());
    const Matrix eps = uniform_column(n, m.rng);
    tape.clear();
    const Matrix fake =
        m.gen->decode(m.gen->store().bind_constant(tape), tape.constant(h), tape.constant(y))
            .value();
    const Step critic[] = {{&m.critic->store(), m.adam.critic.get()}};
    Critic<float>::Loss l;
    train_step<float>(tape, critic, [&](nn::Tape<float>& t, const std::vector<Bound>& p) {
      const Var yv = t.constant(y), real = t.constant(x), generated = t.constant(fake);
      l = m.critic->wgan_gp_loss(p[0], real, generated, yv, eps,
                                 static_cast<float>(m.config.gp_lambda));
      return l.loss;
    });
    critic_loss = mean_value(l.loss);
    wasserstein = mean_value(l.real_score) - mean_value(l.fake_score);
    gp = mean_value(l.penalty);
  }
  const Matrix y = one_hot<float>(draw_labels(d, n, m.rng), m.config.classes);
  for (Eigen::Index i = 0; i < h.size(); ++i) h.data()[i] = static_cast<float>(m.rng.normal());
  // The critic is read, not trained, in this step.
  const Step decoder[] = {{&m.gen->store(), m.adam.decoder.get()}, {&m.critic->store()}};
  const Var loss =
      train_step<float>(tape, decoder, [&](nn::Tape<float>& t, const std::vector<Bound>& p) {
        const Var yv = t.constant(y);
        return nn::scale(nn::mean((*m.critic)(p[1], m.gen->decode(p[0], t.constant(h), yv), yv)),
                         -1.0f);
      });
  return {mean_value(loss), critic_loss, wasserstein, 0, 0, gp};
}

namespace {

// The classifier alone on real clips (Baseline_T/G): g_steps cross-entropy updates.
LossTerms classifier_iteration(ActganModel& m, const ActionClips& d, nn::Tape<float>& tape) {
  std::vector<Matrix> real;
  std::vector<int> labels;
  double ce = 0;
  for (int k = 0; k < m.training.g_steps; ++k) {
    draw_clips(d, m.training.batch, m.rng, real, labels);
    const Step cls[] = {{&m.cls->store(), m.adam.cls.get()}};
    const Var loss =
        train_step<float>(tape, cls, [&](nn::Tape<float>& t, const std::vector<Bound>& p) {
          return nn::softmax_cross_entropy((*m.cls)(p[0], constants(t, real)), labels);
        });
    ce += mean_value(loss) / m.training.g_steps;
  }
  return {ce, 0, 0, 0, ce, 0};
}

// The discriminator's loss on real and generated clips (frames as the discriminator sees them):
// binary cross-entropy of the BiLSTM, or the critic's Wasserstein loss with the gradient penalty
// at random points between the two (eps drawn from rng, one per clip).
Var discriminator_loss(const ActganModel& m, const nn::Bound<float>& pd,
                       const std::vector<Var>& real, const std::vector<Var>& fake, Var y,
                       Rng& rng) {
  const auto& c = m.config;
  if (!m.clip_critic) {
    const Eigen::Index n = y.rows();
    return nn::add(nn::bce_with_logits((*m.disc)(pd, discriminator_input(c, real, y)),
                                       Matrix(Matrix::Ones(n, 1))),
                   nn::bce_with_logits((*m.disc)(pd, discriminator_input(c, fake, y)),
                                       Matrix(Matrix::Zero(n, 1))));
  }
  const Var x = nn::concat_cols<float>(real), g = nn::concat_cols<float>(fake);  // [B, T·P]
  return m.clip_critic
      ->wgan_gp_loss(pd, x, g, y, uniform_column(y.rows(), rng), static_cast<float>(c.gp_lambda))
      .loss;
}

// The generator's adversarial term for its frames: -log D (non-saturating), or -critic.
Var adversarial_term(const ActganModel& m, const nn::Bound<float>& pd,
                     const std::vector<Var>& frames, Var y) {
  if (!m.clip_critic)
    return nn::bce_with_logits((*m.disc)(pd, discriminator_input(m.config, frames, y)),
                               Matrix(Matrix::Ones(y.rows(), 1)));
  return nn::scale(nn::mean((*m.clip_critic)(pd, nn::concat_cols<float>(frames), y)), -1.0f);
}

// One discriminator update against a fresh batch of real and generated clips; its loss.
double discriminator_step(ActganModel& m, const ActionClips& d, nn::Tape<float>& tape) {
  const auto& c = m.config;
  const int n = m.training.batch;
  std::vector<Matrix> real;
  std::vector<int> labels;
  draw_clips(d, n, m.rng, real, labels);
  const Matrix y = one_hot<float>(labels, c.classes);
  const auto noise = draw_generator_noise<float>(c, n, d.length, m.rng);
  tape.clear();
  const std::vector<Matrix> fake = values(
      generate_from_noise(*m.gen, m.gen->store().bind_constant(tape), tape, y, noise).frames);
  const Step disc[] = {{&m.discriminator_store(), m.adam.disc.get()}};
  return mean_value(
      train_step<float>(tape, disc, [&](nn::Tape<float>& t, const std::vector<Bound>& p) {
        const auto real_seen =
            with_instance_noise(constants(t, real), m.training.disc_noise, m.rng);  // real first
        const auto fake_seen =
            with_instance_noise(constants(t, fake), m.training.disc_noise, m.rng);
        return discriminator_loss(m, p[0], real_seen, fake_seen, t.constant(y), m.rng);
      }));
}

}  // namespace

LossTerms actgan_gan_iteration(ActganModel& m, const ActionClips& d, nn::Tape<float>& tape) {
  if (m.training.classifier_only) return classifier_iteration(m, d, tape);
  const auto& tr = m.training;
  const auto& c = m.config;
  const int n = tr.batch;
  std::vector<Matrix> real;
  std::vector<int> labels;
  double disc_loss = 0;
  for (int k = 0; k < tr.d_steps; ++k) disc_loss = discriminator_step(m, d, tape);
  double total = 0, adv = 0, smooth = 0, cycle = 0;
  for (int k = 0; k < tr.g_steps; ++k) {
    draw_clips(d, n, m.rng, real, labels);
    const Matrix y = one_hot<float>(labels, c.classes);
    const auto noise = draw_generator_noise<float>(c, n, d.length, m.rng);
    // The generator (--freeze-decoder, the authors' code: its pre-trained decoder held as it is)
    // and the classifier (with the cycle loss) train; the discriminator is read, not trained.
    const Step stores[] = {
        {&m.gen->store(), m.adam.gen.get(), tr.train_decoder ? "" : "gen.decoder."},
        {&m.discriminator_store()},
        {&m.cls->store(), c.classifier ? m.adam.cls.get() : nullptr}};
    Var a, o, cyc;
    const Var loss =
        train_step<float>(tape, stores, [&](nn::Tape<float>& t, const std::vector<Bound>& p) {
          const Var yv = t.constant(y);
          const GeneratedSequences<float> g = generate_from_noise(*m.gen, p[0], t, y, noise);
          a = adversarial_term(m, p[1], with_instance_noise(g.frames, tr.disc_noise, m.rng), yv);
          o = smoothness(c, g);
          Var l = nn::add(a, o);
          cyc = t.constant(Matrix::Zero(1, 1));
          if (c.classifier) {
            cyc = nn::add(nn::softmax_cross_entropy((*m.cls)(p[2], constants(t, real)), labels),
                          nn::softmax_cross_entropy((*m.cls)(p[2], g.frames), labels));
            l = nn::add(l, nn::scale(cyc, static_cast<float>(c.gamma)));
          }
          return l;
        });
    total += mean_value(loss) / tr.g_steps;
    adv += mean_value(a) / tr.g_steps;
    smooth += mean_value(o) / tr.g_steps;
    cycle += mean_value(cyc) / tr.g_steps;
  }
  return {total, disc_loss, adv, smooth, cycle, 0};
}

namespace {

// The model to train: its configuration from the options and the data file.
ActganModel describe_model(const ActganTrainOptions& opt, const io::SkeletonFile& s,
                           const ActionClips& clips) {
  ActganModel m;
  m.config = opt.net;
  m.config.pose = clips.pose;
  m.config.classes = static_cast<int>(s.class_names.size());
  m.training = opt.training;
  m.training.disc_lr = m.training.discriminator_lr();  // the rate in use (0 means --lr) is recorded
  m.class_names = s.class_names;
  m.parents = s.parents;
  m.joint_names = s.joint_names;
  m.normalization = s.normalization;
  m.frame_rate = s.frame_rate;
  m.length = clips.length;
  m.data = opt.input;
  return m;
}

// The loss lines' validation columns: opt.validate on the held-out clips (none without them).
Validation validation_evaluation(const ActganTrainOptions& opt, const ActganModel& m,
                                 const ActionClips& validation) {
  if (validation.size() == 0) return {};
  if (!opt.validate) throw Error("train_actgan: validation subjects but no validation measure");
  log::info(
      "validation: {} clips of subjects {} held out of training; the log's {} columns compare "
      "generated sequences with them",
      validation.size(), fmt::join(m.training.validation_subjects, ","),
      fmt::join(ActganModel::validation_columns(), " / "));
  return {ActganModel::validation_columns(),
          [&opt, &m, &validation] { return opt.validate(m, validation); }};
}

// --resume: the checkpoint's networks and training state; the settings (and --iterations) are
// this run's.
void resume_from(ActganModel& m, const std::string& ckpt) {
  ActganModel ck = load_actgan_model(ckpt);
  check_resumable(ck, m, ckpt);
  m.gen = std::move(ck.gen);
  m.disc = std::move(ck.disc);
  m.clip_critic = std::move(ck.clip_critic);
  m.cls = std::move(ck.cls);
  m.critic = std::move(ck.critic);
  take_training_state(m, std::move(ck));
}

// Appends sequence q of `s` to `c`; every clip has `length` frames (the first sets it).
void append_clip(const io::SkeletonFile& s, std::size_t q, const std::string& path, int& length,
                 ActionClips& c) {
  const auto n = static_cast<int>(s.length(q));
  if (length == 0) length = n;
  if (n != length)
    throw InvalidInput(
        fmt::format("sequences of {} and {} frames: cut equal clips with skel2h5 --length", length,
                    n),
        path);
  c.frames.insert(c.frames.end(),
                  s.poses.begin() + static_cast<std::ptrdiff_t>(s.offsets[q]) * c.pose,
                  s.poses.begin() + static_cast<std::ptrdiff_t>(s.offsets[q + 1]) * c.pose);
  c.labels.push_back(s.labels[q]);
}

// UsageError unless every validation subject performs some of the training sequences.
void check_validation_subjects(const io::SkeletonFile& s, const std::vector<std::int32_t>& subjects,
                               const std::string& path) {
  if (subjects.empty()) return;
  if (s.subjects.empty())
    throw UsageError(fmt::format(
        "{} names no subjects: --validation-subjects needs them (skel2h5 input with subjects)",
        path));
  for (const auto v : subjects) {
    bool found = false;
    for (std::size_t q = 0; q < s.sequences() && !found; ++q)
      found = s.subjects[q] == v && (s.test.empty() || !s.test[q]);
    if (!found)
      throw UsageError(fmt::format(
          "validation subject {} performs none of the training sequences of {}", v, path));
  }
}

}  // namespace

ActionData training_clips(const io::SkeletonFile& s, const std::string& path,
                          const std::vector<std::int32_t>& validation_subjects) {
  if (s.dims != 3) throw InvalidInput("ActGAN needs 3-D joints", path);
  check_validation_subjects(s, validation_subjects, path);
  ActionData d;
  d.train.pose = d.validation.pose = static_cast<int>(s.frame_size());
  int length = 0;
  for (std::size_t q = 0; q < s.sequences(); ++q) {
    if (!s.test.empty() && s.test[q]) continue;
    const bool held_out = !validation_subjects.empty() &&
                          std::find(validation_subjects.begin(), validation_subjects.end(),
                                    s.subjects[q]) != validation_subjects.end();
    append_clip(s, q, path, length, held_out ? d.validation : d.train);
  }
  d.train.length = d.validation.length = length;
  if (d.train.size() < 2)
    throw InvalidInput(
        fmt::format("{} training sequence(s); ActGAN needs at least 2", d.train.size()), path);
  if (d.train.length < 2) throw InvalidInput("sequences of 1 frame: nothing moves", path);
  if (!s.normalization.present())
    log::warn(
        "{} is not normalized (skel2h5 without --raw normalizes): training on raw coordinates",
        path);
  return d;
}

void apply_learning_defaults(ActganConfig& net, ActganTraining& training) {
  net.discriminator = Discriminator::critic;
  training.d_steps = 5;
  net.smoothness = Smoothness::action;
  net.start = LatentStart::normal;
}

void apply_paper_form(ActganConfig& net, ActganTraining& training) {
  net.discriminator = Discriminator::bilstm;
  training.d_steps = 1;
  net.smoothness = Smoothness::both;
  net.start = LatentStart::uniform;
}

ActganTrainer::ActganTrainer(const ActganTrainOptions& opt, const io::SkeletonFile& s)
    : opt_(opt),
      data_(training_clips(s, opt.input, opt.training.validation_subjects)),
      m_(describe_model(opt, s, data_.train)) {}

// Pre-training iterations, then the GAN's.
LossTerms ActganTrainer::step(std::int64_t done) {
  const std::int64_t pretrain = m_.training.pretrain_iterations;
  if (done == pretrain + 1 && pretrain > 0)
    log::info("decoder pre-trained; the GAN from iteration {}", done);
  return done <= pretrain ? actgan_pretrain_iteration(m_, data_.train, tape_)
                          : actgan_gan_iteration(m_, data_.train, tape_);
}

Trainer ActganTrainer::hooks() {
  return {.output = opt_.output,
          .iterations = m_.training.pretrain_iterations + m_.training.iterations,
          .iterations_option = "--pretrain-iterations + --iterations",
          .initialise = [this] { m_.initialize(); },
          .resume = [this](const std::string& ckpt) { resume_from(m_, ckpt); },
          .prepare =
              [this] {
                const ActionClips& clips = data_.train;
                log::info(
                    "{}: {} training clips of {} frames, {} classes, {} values per pose; {} + {} "
                    "iterations",
                    opt_.input, clips.size(), clips.length, m_.class_names.size(), clips.pose,
                    m_.training.pretrain_iterations, m_.training.iterations);
              },
          .validation = [this] { return validation_evaluation(opt_, m_, data_.validation); },
          .names = ActganModel::loss_columns(),
          .step = [this](std::int64_t done) { return step(done); },
          .save = [this](const std::string& path,
                         bool force) { save_actgan_model(path, m_, {opt_.input}, force); }};
}

}  // namespace df::models
