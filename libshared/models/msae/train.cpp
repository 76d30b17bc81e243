#include "models/msae/train.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>

#include "core/error.h"
#include "core/log.h"
#include "geometry/geodesic_distance.h"
#include "io/acap_file.h"
#include "models/common/splocs.h"
#include "models/common/training.h"
#include "models/msae/diagnosis.h"
#include "models/msae/settings.h"

namespace df::models {

void check_msae_options(const MsaeTrainOptions& opt) {
  const auto& t = opt.training;
  check_ranges(view(msae_settings(), opt.net, t));
  opt.run.check();
  if (opt.net.kz.size() != opt.net.d.size())
    throw UsageError("--kz and --d need one value per level");
  if (t.separate && t.iterations < static_cast<std::int64_t>(opt.net.kz.size()))
    throw UsageError("--separate needs at least one iteration per level");
  if (!opt.test_list.empty() && opt.train_list.empty()) throw UsageError("--test needs --train");
  // With y = tanh(z C) a C scaled by 1/S saturates the decoder's first tanh instead.
  if (t.start_scale != 1 &&
      (opt.net.started_levels() == 0 || opt.net.decoder_fc != MsaeActivation::linear))
    throw UsageError("--start-scale needs --init local or local-all and --decoder-fc linear");
}

namespace {

// Refuses to resume a checkpoint made with other settings (the result would be neither run).
void check_resumable(const MsaeModel& ck, const MsaeModel& want, const std::string& path) {
  require_same_settings(view(msae_settings(), ck.config, ck.training),
                        view(msae_settings(), want.config, want.training), path);
  auto differs = [&](const char* what, const auto& a, const auto& b) {
    require_same_setting(what, a, b, path);
  };
  if (ck.training.separate)
    differs("iterations (separate training divides them among the levels)", ck.training.iterations,
            want.training.iterations);
  differs("vertices", ck.tmpl.vertices.rows(), want.tmpl.vertices.rows());
  if (ck.split.train != want.split.train || ck.split.validation != want.split.validation ||
      ck.split.test != want.split.test)
    throw InvalidInput("checkpoint was trained on another split of the data", path);
}

// Frames of a list file: names of /frames/names or indices.
std::vector<std::int64_t> read_list(const std::string& path,
                                    const std::map<std::string, std::int64_t>& by_name,
                                    std::int64_t n_frames) {
  std::ifstream in(path);
  if (!in) throw IOError("cannot read the list", path);
  std::vector<std::int64_t> frames;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string entry = line.substr(first, line.find_last_not_of(" \t\r") + 1 - first);
    std::int64_t f = -1;
    if (auto it = by_name.find(entry); it != by_name.end()) {
      f = it->second;
    } else if (entry.find_first_not_of("0123456789") == std::string::npos && entry.size() < 19) {
      f = std::stoll(entry);
      if (f >= n_frames) f = -1;
    }
    const std::string where = fmt::format("{}:{}", path, number);
    if (f < 0)
      throw InvalidInput(
          fmt::format("'{}' is neither a frame name of the data nor a frame index below {}", entry,
                      n_frames),
          where);
    if (std::find(frames.begin(), frames.end(), f) != frames.end())
      throw InvalidInput(fmt::format("frame '{}' is listed twice", entry), where);
    frames.push_back(f);
  }
  std::sort(frames.begin(), frames.end());
  return frames;
}

// A random round(fraction × n) of `held` (by the seed) moves to `validation`.
void carve_validation(MsaeSplit& s, double fraction, std::uint64_t seed) {
  const auto n =
      static_cast<std::size_t>(std::llround(fraction * static_cast<double>(s.test.size())));
  if (n == 0) return;
  std::vector<std::int64_t> held = s.test;
  Rng rng(seed, 0x7a1);
  for (std::size_t k = 0; k < n; ++k) std::swap(held[k], held[k + rng.below(held.size() - k)]);
  s.validation.assign(held.begin(), held.begin() + static_cast<std::ptrdiff_t>(n));
  std::sort(s.validation.begin(), s.validation.end());
  s.test.assign(held.begin() + static_cast<std::ptrdiff_t>(n), held.end());
  std::sort(s.test.begin(), s.test.end());
}

// Rows of `data` as one matrix.
nn::Matrix<float> gather(const nn::Matrix<float>& data, const std::vector<std::int64_t>& frames) {
  nn::Matrix<float> out(static_cast<Eigen::Index>(frames.size()), data.cols());
  for (std::size_t k = 0; k < frames.size(); ++k)
    out.row(static_cast<Eigen::Index>(k)) = data.row(frames[k]);
  return out;
}

// Mean over shapes of ‖X − X̂‖² through every level (the recon term's units), in chunks; the
// reconstructions land in *recon.
double reconstruction_error(const MsaeNet<float>& net, const nn::Matrix<float>& shapes,
                            nn::Matrix<float>* recon) {
  double sum = 0;
  recon->resize(shapes.rows(), shapes.cols());
  constexpr Eigen::Index kChunk = 64;
  for (Eigen::Index r = 0; r < shapes.rows(); r += kChunk) {
    const Eigen::Index n = std::min(kChunk, shapes.rows() - r);
    const nn::Matrix<float> x = shapes.middleRows(r, n);
    recon->middleRows(r, n) = net.reconstruct(x, net.config().levels());
    sum += static_cast<double>((x - recon->middleRows(r, n)).squaredNorm());
  }
  return sum / static_cast<double>(shapes.rows());
}

// A batch of `size` shapes drawn with replacement from `frames`, as its distinct shapes (in order
// of first draw) and how often each was drawn: the same loss and gradient as the full batch at
// a fraction of the cost when there are few training shapes (the paper's 1:9 splits).
void draw_batch(const nn::Matrix<float>& data, const std::vector<std::int64_t>& frames, int size,
                Rng& rng, nn::Matrix<float>& batch, nn::Matrix<float>& weights) {
  std::vector<std::size_t> slot(frames.size(), SIZE_MAX), order;
  std::vector<float> count;
  for (int b = 0; b < size; ++b) {
    const auto k = static_cast<std::size_t>(rng.below(frames.size()));
    if (slot[k] == SIZE_MAX) slot[k] = order.size(), order.push_back(k), count.push_back(0);
    count[slot[k]] += 1;
  }
  batch.resize(static_cast<Eigen::Index>(order.size()), data.cols());
  weights.resize(static_cast<Eigen::Index>(order.size()), 1);
  for (std::size_t r = 0; r < order.size(); ++r) {
    batch.row(static_cast<Eigen::Index>(r)) = data.row(frames[order[r]]);
    weights(static_cast<Eigen::Index>(r), 0) = count[r];
  }
}

// --synthetic: `count` shapes the decoders make from recombined codes of the batch's shapes,
// appended to the batch; together they weigh `share` × the batch's weight. Costs one more
// forward pass of the real shapes per iteration: their codes are needed before the batch exists,
// and the loss's own forward pass comes after (taking the previous iteration's codes instead would
// change the draws and need them in the checkpoint).
void add_synthetic_shapes(const MsaeNet<float>& net, int count, double share, Rng& rng,
                          nn::Matrix<float>& batch, nn::Matrix<float>& weights) {
  const nn::Matrix<float> shapes = net.recombined_shapes(batch, count, rng);
  const Eigen::Index real = batch.rows();
  const float each = static_cast<float>(share * static_cast<double>(weights.sum()) / count);
  batch.conservativeResize(real + count, Eigen::NoChange);
  batch.bottomRows(count) = shapes;
  weights.conservativeResize(real + count, Eigen::NoChange);
  weights.bottomRows(count).setConstant(each);
}

// Which level an iteration trains: all (−1) jointly, or one after another when separate.
int stage_of(const MsaeModel& m, std::int64_t done) {
  if (!m.training.separate) return -1;
  const auto L = static_cast<std::int64_t>(m.config.levels());
  return static_cast<int>(std::min(L - 1, (done - 1) * L / m.training.iterations));
}

}  // namespace

MsaeSplit split_shapes(const std::vector<std::int64_t>& offsets, const MsaeTraining& t) {
  MsaeSplit s;
  const std::int64_t n = offsets.back();
  if (t.split == SplitKind::sequence) {
    for (std::size_t q = 0; q + 1 < offsets.size(); ++q)
      for (std::int64_t f = offsets[q]; f < offsets[q + 1]; ++f)
        ((f - offsets[q]) % t.every == 0 ? s.train : s.test).push_back(f);
  } else if (t.split == SplitKind::collection) {
    std::vector<std::int64_t> all(static_cast<std::size_t>(n));
    std::iota(all.begin(), all.end(), std::int64_t{0});
    Rng rng(t.seed, 0x5e9117);
    const auto n_train = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::llround(t.train_fraction * static_cast<double>(n))));
    for (std::size_t k = 0; k < n_train && k < all.size(); ++k)
      std::swap(all[k], all[k + rng.below(all.size() - k)]);
    s.train.assign(all.begin(),
                   all.begin() + static_cast<std::ptrdiff_t>(std::min(n_train, all.size())));
    s.test.assign(all.begin() + static_cast<std::ptrdiff_t>(std::min(n_train, all.size())),
                  all.end());
    std::sort(s.train.begin(), s.train.end());
    std::sort(s.test.begin(), s.test.end());
  } else {
    throw UsageError("--split must be sequence or collection (or give --train/--test lists)");
  }
  carve_validation(s, t.validation_fraction, t.seed);
  return s;
}

MsaeSplit split_from_lists(const std::vector<std::string>& frame_names,
                           const std::string& train_list, const std::string& test_list) {
  std::map<std::string, std::int64_t> by_name;
  for (std::size_t k = 0; k < frame_names.size(); ++k)
    by_name.emplace(frame_names[k], static_cast<std::int64_t>(k));
  const auto n = static_cast<std::int64_t>(frame_names.size());
  MsaeSplit s;
  s.train = read_list(train_list, by_name, n);
  if (!test_list.empty()) {
    s.test = read_list(test_list, by_name, n);
    for (auto f : s.test)
      if (std::binary_search(s.train.begin(), s.train.end(), f))
        throw InvalidInput(fmt::format("frame '{}' is in both the training and the test list",
                                       frame_names[static_cast<std::size_t>(f)]),
                           test_list);
  } else {
    for (std::int64_t f = 0; f < n; ++f)
      if (!std::binary_search(s.train.begin(), s.train.end(), f)) s.test.push_back(f);
  }
  return s;
}

namespace {

// The model's configuration, template, normalization and split, from the options and the data.
MsaeModel describe_model(const MsaeTrainOptions& opt, const CommonOptions& common,
                         const io::AcapReader& in) {
  MsaeModel m;
  m.config = opt.net;
  m.training = opt.training;
  m.training.seed = common.seed;
  if (!opt.train_list.empty()) m.training.split = SplitKind::lists;
  m.history = in.history();
  m.tmpl = in.read_template();
  m.normalization = in.normalization();
  m.split = opt.train_list.empty()
                ? split_shapes(in.offsets(), m.training)
                : split_from_lists(in.frame_names(), opt.train_list, opt.test_list);
  if (!opt.train_list.empty())
    carve_validation(m.split, m.training.validation_fraction, m.training.seed);
  m.split.data = opt.input;
  if (m.split.train.size() < 2)
    throw InvalidInput(
        fmt::format("{} training shape(s): the autoencoders need at least 2 to learn deformations "
                    "(use a smaller --every, a larger --train-fraction or a longer --train list)",
                    m.split.train.size()),
        opt.input);
  return m;
}

// `count` vertices by farthest-point sampling among `allowed` (geodesic distance), starting at
// `first` (a vertex of `allowed`).
std::vector<int> farthest_points(geometry::GeodesicRows& geodesic, const std::vector<int>& allowed,
                                 int first, int count) {
  std::vector<int> chosen{first};
  std::vector<float> nearest(allowed.size(), std::numeric_limits<float>::max());
  while (static_cast<int>(chosen.size()) < count) {
    const auto& row = geodesic.row(chosen.back());
    std::size_t best = 0;
    for (std::size_t a = 0; a < allowed.size(); ++a) {
      nearest[a] = std::min(nearest[a], row[allowed[a]]);
      if (nearest[a] > nearest[best]) best = a;
    }
    chosen.push_back(allowed[best]);  // a repeat only when every allowed vertex is chosen
  }
  return chosen;
}

// --centres spread: level-0 blocks' centres by farthest-point sampling over the mesh (from the
// vertex farthest from vertex 0); an attention child's within its parent component's radius
// (from the parent's centre); a level block without attention over the whole mesh.
std::vector<std::vector<int>> spread_centres(const MsaeNet<float>& net,
                                             geometry::GeodesicRows& geodesic) {
  const int V = net.n_vertices();
  std::vector<int> all(static_cast<std::size_t>(V));
  std::iota(all.begin(), all.end(), 0);
  const auto& row0 = geodesic.row(0);
  int far = 0;
  for (int i = 0; i < V; ++i)
    if (row0[i] > row0[far]) far = i;
  std::vector<std::vector<int>> out(net.blocks().size());
  for (std::size_t b = 0; b < net.blocks().size(); ++b) {
    const auto& bl = net.blocks()[b];
    if (bl.parent < 0 || !net.config().attention) {
      out[b] = farthest_points(geodesic, all, far, bl.kz);
      continue;
    }
    const int centre = out[static_cast<std::size_t>(bl.parent)][static_cast<std::size_t>(bl.slot)];
    const double radius = net.config().d[static_cast<std::size_t>(bl.level - 1)];
    const auto& row = geodesic.row(centre);
    std::vector<int> region;
    for (int i = 0; i < V; ++i)
      if (row[i] < radius) region.push_back(i);
    out[b] = farthest_points(geodesic, region, centre, bl.kz);
  }
  return out;
}

// A checkpoint whose distances put a mesh's other parts at the diameter (before stop 78) cannot go
// on with bridged ones: Omega would mix two measures. On a mesh of one part the two agree.
void refuse_unbridged(const MsaeModel& ck, const geometry::GeodesicRows& geodesic,
                      const std::string& ckpt) {
  if (ck.geodesic_method == GeodesicMethod::heat && geodesic.parts() > 1)
    throw InvalidInput(
        fmt::format("the checkpoint's geodesic distances were made before parts were bridged "
                    "(other parts at the diameter) and this mesh has {} separate parts, so its "
                    "components' radii would change mid-run; remove it and train anew",
                    geodesic.parts()),
        ckpt);
}

// --resume: the checkpoint's weights, training state, collapse record and geodesic rows; returns
// the geodesic distances on the template with its rows kept.
std::unique_ptr<geometry::GeodesicRows> resume_from(MsaeModel& m, const std::string& ckpt) {
  MsaeModel ck = load_msae_model(ckpt);
  check_resumable(ck, m, ckpt);
  m.net = std::move(ck.net);
  m.log_validation_erms = ck.log_validation_erms;  // its log's columns go on as they began (if any)
  m.collapse = std::move(ck.collapse);  // a collapse warned of goes on being dated from then
  m.collapse_since = ck.collapse_since;
  m.geodesic_diameter = ck.geodesic_diameter;
  auto geodesic =
      std::make_unique<geometry::GeodesicRows>(m.tmpl.vertices, m.tmpl.faces, m.geodesic_diameter);
  refuse_unbridged(ck, *geodesic, ckpt);
  for (std::size_t k = 0; k < ck.geodesic_sources.size(); ++k)
    geodesic->keep(ck.geodesic_sources[k], ck.geodesic_rows[k]);
  take_training_state(m, std::move(ck));
  return geodesic;
}

// A new model: weights from the seed, the geodesic distances on the template, the centres placed
// (--centres spread); returns the distances.
std::unique_ptr<geometry::GeodesicRows> start_afresh(MsaeModel& m) {
  m.initialize();
  log::info("geodesic distances on the template (heat method; {} vertices)",
            m.tmpl.vertices.rows());
  auto geodesic = std::make_unique<geometry::GeodesicRows>(m.tmpl.vertices, m.tmpl.faces);
  m.geodesic_diameter = geodesic->diameter();
  if (m.config.centres == Centres::spread) m.net->place_centres(spread_centres(*m.net, *geodesic));
  return geodesic;
}

// --init local: a block's components start as the local decomposition of what it is fed — SPLOCS
// on those rows (for AE₀ the training shapes' features) with K_z components whose support maps end
// at the block's radius d, the algorithm of the local linear reference (fit-baseline --method
// splocs-acap) — orthonormalised symmetrically (Löwdin: of all orthonormal bases of their span,
// the one nearest the components, so that each stays where it was and the block's tied weights
// start as the projection onto their span). A component SPLOCS leaves empty keeps its random
// row: a zero row of C is a stationary point that no gradient leaves.
void start_block_locally(MsaeModel& m, int b, const nn::Matrix<float>& input,
                         geometry::GeodesicRows& geodesic) {
  const auto& block = m.net->blocks()[static_cast<std::size_t>(b)];
  SplocsOptions o;
  o.components = block.kz;
  o.d_max = m.config.d[static_cast<std::size_t>(block.level)];
  o.d_min = o.d_max / 4;
  const Splocs local = fit_splocs(
      input.cast<double>(), o, [&](int i) -> Eigen::VectorXf { return geodesic.row(i); }, 9);
  std::vector<Eigen::Index> live;
  for (Eigen::Index k = 0; k < local.components.rows(); ++k)
    if (local.components.row(k).squaredNorm() > 0) live.push_back(k);
  const auto n = static_cast<Eigen::Index>(live.size());
  if (n == 0) {
    log::warn("--init {}: SPLOCS found none of block {}'s components; it starts random",
              m.config.init, b);
    return;
  }
  nn::Matrix<double> basis(n, local.components.cols());
  for (Eigen::Index r = 0; r < n; ++r)
    basis.row(r) = local.components.row(live[static_cast<std::size_t>(r)]);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> gram(basis * basis.transpose());
  // Two components nearly parallel leave an eigenvalue near zero; floored relative to the largest
  // (the components' scale is the data's), their difference is not blown up to a unit row of noise.
  const double floor = 1e-10 * std::max(gram.eigenvalues().maxCoeff(), 1e-300);
  log::debug("--init {}: block {}'s {} SPLOCS components, Gram eigenvalues {:.3g} to {:.3g}",
             m.config.init, b, n, gram.eigenvalues().minCoeff(), gram.eigenvalues().maxCoeff());
  if (gram.eigenvalues().minCoeff() < floor)
    log::warn("--init {}: block {}'s SPLOCS components are nearly linearly dependent",
              m.config.init, b);
  const Eigen::VectorXd inv_sqrt = gram.eigenvalues().cwiseMax(floor).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd lowdin =
      gram.eigenvectors() * inv_sqrt.asDiagonal() * gram.eigenvectors().transpose();
  nn::Matrix<float> C = m.net->store().value(block.c);
  const nn::Matrix<double> orthonormal = lowdin * basis;
  for (Eigen::Index r = 0; r < n; ++r)
    C.row(live[static_cast<std::size_t>(r)]) = orthonormal.row(r).cast<float>();
  if (n < C.rows())
    log::warn("--init {}: SPLOCS found {} of block {}'s {} components; the others start random",
              m.config.init, n, b, C.rows());
  m.net->start_block(b, C, m.training.start_scale);
}

// --init local: AE₀ from the training shapes; local-all: then every level in turn, each block
// from the training shapes' inputs to it through the levels already started.
void start_from_local_decomposition(MsaeModel& m, const nn::Matrix<float>& train,
                                    geometry::GeodesicRows& geodesic) {
  const int levels = m.config.started_levels();
  log::info("--init {}: {} from SPLOCS on the {} training shapes", m.config.init,
            levels == 1 ? "level 0's components" : "every block's components", train.rows());
  start_block_locally(m, 0, train, geodesic);
  for (int l = 1; l < levels; ++l) {
    std::vector<nn::Matrix<float>> inputs;
    m.net->reconstruct(train, l + 1, nullptr, &inputs);
    for (int b = m.net->level_begin()[static_cast<std::size_t>(l)];
         b < m.net->level_begin()[static_cast<std::size_t>(l) + 1]; ++b)
      start_block_locally(m, b, inputs[static_cast<std::size_t>(b)], geodesic);
  }
}

// Ω's masks around the current centres (their geodesic rows solved first, in parallel).
std::vector<nn::Matrix<float>> current_sparsity_masks(const MsaeModel& m,
                                                      geometry::GeodesicRows& geodesic) {
  const auto peaks = m.net->centres();
  std::vector<int> sources;
  for (const auto& c : peaks) sources.insert(sources.end(), c.begin(), c.end());
  geodesic.prepare(sources);
  const auto centres = m.config.centre_separation > 0
                           ? m.net->separated_centres(
                                 [&](int c) -> const Eigen::VectorXf& { return geodesic.row(c); })
                           : peaks;
  return m.net->sparsity_masks(centres,
                               [&](int c) -> const Eigen::VectorXf& { return geodesic.row(c); });
}

// The geodesic rows of the final centres, for the model file.
void remember_geodesics(MsaeModel& m, geometry::GeodesicRows& geodesic) {
  m.geodesic_sources.clear();
  m.geodesic_rows.clear();
  for (const auto& c : m.net->centres())
    for (int s : c)
      if (std::find(m.geodesic_sources.begin(), m.geodesic_sources.end(), s) ==
          m.geodesic_sources.end()) {
        m.geodesic_sources.push_back(s);
        m.geodesic_rows.push_back(geodesic.row(s));
      }
}

// One iteration: a batch of training shapes drawn with the model's RNG, Ω's masks around the
// current centres, the gradient block by block, one Adam step (of the level in training when
// separate: a new Adam at each level's start, the other levels' gradients dropped).
LossTerms training_step(MsaeModel& m, const nn::Matrix<float>& data,
                        geometry::GeodesicRows& geodesic, std::int64_t done,
                        nn::Matrix<float>& batch, nn::Matrix<float>& weights) {
  draw_batch(data, m.split.train, m.training.batch, m.rng, batch, weights);
  if (m.training.synthetic > 0)
    add_synthetic_shapes(*m.net, m.training.synthetic, m.training.synthetic_weight, m.rng, batch,
                         weights);
  const auto lambda = current_sparsity_masks(m, geodesic);
  const int stage = stage_of(m, done);
  if (stage > 0 && stage_of(m, done - 1) != stage) {
    m.adam = m.make_adam(done - 1);
    log::info("separate training: level {} from iteration {} (levels below it frozen; rate {:.3g})",
              stage, done, m.adam->learning_rate());
  }
  m.net->store().zero_grad();
  const MsaeLossTerms terms = m.net->loss_and_gradient(
      batch, lambda, stage < 0 ? std::vector<int>{} : std::vector<int>{stage}, &weights);
  if (stage > 0)
    for (int l = 0; l < stage; ++l)
      for (int p : m.net->level_parameters(l)) m.net->store().grad(p).setZero();
  m.adam->step(m.net->store().values(), m.net->store().grads());
  if (m.config.support == Support::hard) m.net->project_onto_support(lambda);
  if (m.config.support == Support::proximal)
    m.net->proximal_sparsity(lambda, m.adam->last_step_sizes(),
                             stage < 0 ? std::vector<int>{} : std::vector<int>{stage});
  return {terms.total, terms.recon, terms.sparsity, terms.latent};
}

// The loss lines' validation columns: the validation shapes' feature error and, for a fresh run
// or a checkpoint taken before the first loss line (its log has no columns yet), their E_rms; a
// log that began without it goes on without it. None without validation shapes.
Validation validation_measure(const MsaeTrainOptions& opt, MsaeModel& m,
                              const nn::Matrix<float>& validation, MsaeShapeMeasure& erms) {
  if (validation.rows() == 0) return {};
  Validation v{{"validation"}, {}};
  if (opt.position_error && (m.log.empty() || m.log_validation_erms)) {
    m.log_validation_erms = true;
    erms = opt.position_error(m, m.split.validation);
    v.names.push_back("validation_erms");
  }
  v.measure = [&m, &validation, &erms]() -> LossTerms {
    nn::Matrix<float> recon;
    LossTerms values = {reconstruction_error(*m.net, validation, &recon)};
    if (erms) values.push_back(erms(recon));
    return values;
  };
  return v;
}

// After the start: a fresh model's data-dependent start (the training shapes' mean taken out,
// --init local's components) and the line describing the run.
void prepare_data_dependent_start(MsaeModel& m, const nn::Matrix<float>& data,
                                  geometry::GeodesicRows& geodesic, const std::string& input) {
  if (m.config.centre_features && m.iteration == 0)  // a fresh model: the training shapes' mean
    m.net->set_offset(gather(data, m.split.train).colwise().mean());
  if (m.config.started_levels() > 0 && m.iteration == 0)
    start_from_local_decomposition(m, gather(data, m.split.train), geodesic);
  log::info(
      "{}: {} shapes of {} vertices; training on {}, validating on {}, {} held out for testing; {} "
      "blocks in {} levels (K_z {}), {} parameters, {} training",
      input, data.rows(), m.tmpl.vertices.rows(), m.split.train.size(), m.split.validation.size(),
      m.split.test.size(), m.net->blocks().size(), m.config.levels(), fmt::join(m.config.kz, ","),
      m.net->store().size(), m.training.separate ? "separate" : "joint");
}

}  // namespace

void apply_msae_defaults(MsaeConfig& net, MsaeTraining& training) {
  net.centre_features = true;       // no component spent on the mean deformation
  net.support = Support::proximal;  // Omega's weights outside each radius exactly zero
  net.kz = {10, 50};                // second-level blocks as wide as the residual needs
  training.synthetic = 16;  // the encoder learns to invert the decoders beyond the training codes
  net.init = MsaeInit::local;    // AE₀ starts as the training shapes' local components (SPLOCS)
  training.started_rate = 0.01;  // and steps at 1% of the rate: Adam's first steps keep them
}

MsaeTrainer::MsaeTrainer(const MsaeTrainOptions& opt, const CommonOptions& common,
                         const io::AcapReader& in, nn::Matrix<float> features)
    : opt_(opt),
      m_(describe_model(opt, common, in)),
      report_(fmt::format("extract-components --report {} {} shows each component", opt.output,
                          opt.input)),
      data_(std::move(features)),
      validation_(gather(data_, m_.split.validation)) {}

MsaeTrainer::~MsaeTrainer() = default;

// Level 0's collapse, measured on the training shapes at every loss line: a warning while it
// lasts, and the last one in the model file.
void MsaeTrainer::check_collapse() {
  m_.collapse = collapse_signs(m_, data_, m_.split.train).describe(m_.config);
  if (m_.collapse.empty()) return;
  if (m_.collapse_since == 0) m_.collapse_since = m_.iteration;
  log::warn("{}; {}", m_.collapse, report_);
}

Trainer MsaeTrainer::hooks() {
  return {.output = opt_.output,
          .iterations = m_.training.iterations,
          .initialise = [this] { geodesic_ = start_afresh(m_); },
          .resume = [this](const std::string& ckpt) { geodesic_ = resume_from(m_, ckpt); },
          .prepare = [this] { prepare_data_dependent_start(m_, data_, *geodesic_, opt_.input); },
          .validation = [this] { return validation_measure(opt_, m_, validation_, erms_); },
          .names = {"loss", "recon", "sparsity", "latent"},
          .step =
              [this](std::int64_t done) {
                return training_step(m_, data_, *geodesic_, done, batch_, weights_);
              },
          .after_row = [this](const std::vector<double>&) { check_collapse(); },
          .save =
              [this](const std::string& path, bool force) {
                remember_geodesics(m_, *geodesic_);
                save_msae_model(path, m_, {opt_.input}, force);
              },
          .finished =
              [this] {
                if (!m_.collapse.empty())
                  log::warn("the trained model (collapsed since iteration {}): {}; {}",
                            m_.collapse_since, m_.collapse, report_);
              }};
}

}  // namespace df::models
