#include "models/msae/model.h"

#include <fmt/format.h>

#include <cmath>

#include "core/atomic_output.h"
#include "core/error.h"
#include "geometry/mesh_topology.h"
#include "io/file_header.h"
#include "io/schema.h"
#include "models/common/model_file.h"
#include "nn/checkpoint.h"

namespace df::models {

std::vector<std::string> MsaeModel::log_columns() const {
  std::vector<std::string> c = {"iteration", "total", "recon", "sparsity", "latent"};
  if (!split.validation.empty()) c.push_back("validation");
  if (!split.validation.empty() && log_validation_erms) c.push_back("validation_erms");
  return c;
}

void MsaeModel::initialize() {
  auto topo = geometry::mesh_topology(tmpl.faces, static_cast<int>(tmpl.vertices.rows()));
  net = std::make_unique<MsaeNet<float>>(config, static_cast<int>(tmpl.vertices.rows()), topo.edges,
                                         training.seed);
  adam = make_adam();
  rng = Rng(training.seed, 1);
  iteration = 0;
  log.clear();
  unprinted.clear();
}

std::unique_ptr<nn::Adam<float>> MsaeModel::make_adam(std::int64_t start) const {
  nn::AdamOptions ao;
  ao.lr = training.lr;
  if (training.separate_rate == "continue")
    ao.lr *= std::pow(training.lr_decay, static_cast<double>(start) / training.lr_decay_steps);
  ao.schedule = nn::AdamOptions::Schedule::exponential;
  ao.decay_rate = training.lr_decay;
  ao.decay_steps = training.lr_decay_steps;
  return std::make_unique<nn::Adam<float>>(net->store().size(), ao);
}

namespace {
void write_frames(h5::File& f, const std::string& path, const std::vector<std::int64_t>& frames) {
  f.write<std::int64_t>(path, frames, {frames.size()});
}
}  // namespace

void save_msae_model(const std::string& path, const MsaeModel& m,
                     const std::vector<std::string>& inputs, bool force) {
  std::vector<std::filesystem::path> in(inputs.begin(), inputs.end());
  AtomicOutput out(path, AtomicOutput::Kind::file, force, in);
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, path);
    io::write_header(f, "msae-model", {m.history});
    f.create_groups("/config");
    const auto& c = m.config;
    const std::vector<double> kz(c.kz.begin(), c.kz.end());
    f.set_attr("/config", "kz", std::span<const double>(kz));
    f.set_attr("/config", "d", std::span<const double>(c.d));
    f.set_attr("/config", "attention", static_cast<int>(c.attention));
    f.set_attr("/config", "lambda_recon", c.lambda_recon);
    f.set_attr("/config", "lambda_sparse", c.lambda_sparse);
    f.set_attr("/config", "theta", c.theta);
    f.set_attr("/config", "latent", c.latent);
    f.set_attr("/config", "decoder_fc", c.decoder_fc);
    f.set_attr("/config", "decoder_conv", c.decoder_conv);
    f.set_attr("/config", "init", c.init);
    f.set_attr("/config", "centres", c.centres);
    const auto& t = m.training;
    f.set_attr("/config", "iterations", t.iterations);
    f.set_attr("/config", "batch", t.batch);
    f.set_attr("/config", "lr", t.lr);
    f.set_attr("/config", "lr_decay", t.lr_decay);
    f.set_attr("/config", "lr_decay_steps", t.lr_decay_steps);
    f.set_attr("/config", "split", t.split);
    f.set_attr("/config", "every", t.every);
    f.set_attr("/config", "train_fraction", t.train_fraction);
    f.set_attr("/config", "validation_fraction", t.validation_fraction);
    f.set_attr("/config", "separate", static_cast<int>(t.separate));
    f.set_attr("/config", "separate_rate", t.separate_rate);
    f.set_attr("/config", "seed", fmt::format("{}", t.seed));
    write_mesh_model_common(f, m.tmpl, m.normalization, m.log, m.log_columns(), m.unprinted);
    f.create_groups("/split");
    f.set_attr("/split", "data", m.split.data);
    write_frames(f, "/split/train", m.split.train);
    write_frames(f, "/split/validation", m.split.validation);
    write_frames(f, "/split/test", m.split.test);
    f.create_groups("/geodesic");
    f.set_attr("/geodesic", "method", std::string("heat"));
    f.set_attr("/geodesic", "diameter", m.geodesic_diameter);
    if (!m.geodesic_sources.empty()) {
      const std::vector<std::int64_t> sources(m.geodesic_sources.begin(), m.geodesic_sources.end());
      f.write<std::int64_t>("/geodesic/sources", sources, {sources.size()});
      const auto V = static_cast<std::size_t>(m.tmpl.vertices.rows());
      std::vector<float> rows;
      for (const auto& r : m.geodesic_rows) rows.insert(rows.end(), r.data(), r.data() + r.size());
      f.write<float>("/geodesic/distances", rows, {sources.size(), V});
    }
    nn::write_training_state(f, m.net->store(), *m.adam, m.rng, m.iteration);
    f.close();
  }
  out.commit();
}

MsaeModel load_msae_model(const std::string& path) {
  h5::File f = io::open_input(path, "msae-model");
  MsaeModel m;
  m.history = io::read_history(f);
  auto& c = m.config;
  c.kz.clear();
  for (double k : f.attr_doubles("/config", "kz")) c.kz.push_back(static_cast<int>(k));
  c.d = f.attr_doubles("/config", "d");
  if (c.kz.empty() || c.kz.size() != c.d.size())
    throw InvalidInput("/config kz and d must have one value per level", f.where("/config"));
  c.attention = f.attr_int("/config", "attention") != 0;
  c.lambda_recon = f.attr_double("/config", "lambda_recon");
  c.lambda_sparse = f.attr_double("/config", "lambda_sparse");
  c.theta = f.attr_double("/config", "theta");
  c.latent = f.attr_string("/config", "latent");
  // Files written before these settings existed have the network they describe by default.
  auto optional_string = [&](const char* name, const std::string& fallback) {
    return f.has_attr("/config", name) ? f.attr_string("/config", name) : fallback;
  };
  c.decoder_fc = optional_string("decoder_fc", "tanh");
  c.decoder_conv = optional_string("decoder_conv", "transposed");
  c.init = optional_string("init", "glorot");
  c.centres = optional_string("centres", "random");
  auto& t = m.training;
  t.iterations = f.attr_int("/config", "iterations");
  t.batch = static_cast<int>(f.attr_int("/config", "batch"));
  t.lr = f.attr_double("/config", "lr");
  t.lr_decay = f.attr_double("/config", "lr_decay");
  t.lr_decay_steps = f.attr_double("/config", "lr_decay_steps");
  t.split = f.attr_string("/config", "split");
  t.every = static_cast<int>(f.attr_int("/config", "every"));
  t.train_fraction = f.attr_double("/config", "train_fraction");
  t.validation_fraction = f.attr_double("/config", "validation_fraction");
  t.separate = f.attr_int("/config", "separate") != 0;
  t.separate_rate = optional_string("separate_rate", "restart");
  t.seed = std::stoull(f.attr_string("/config", "seed"));
  std::vector<double> log, unprinted;
  read_mesh_model_common(f, m.tmpl, m.normalization, log, unprinted);
  m.log_validation_erms = f.exists("/training/log") &&
                          f.attr_string("/training/log", "columns").find("validation_erms") != std::string::npos;
  m.split.data = f.attr_string("/split", "data");
  m.split.train = f.read<std::int64_t>("/split/train").data;
  m.split.validation = f.read<std::int64_t>("/split/validation").data;
  m.split.test = f.read<std::int64_t>("/split/test").data;
  m.geodesic_diameter = f.attr_double("/geodesic", "diameter");
  if (f.exists("/geodesic/sources")) {
    for (auto s : f.read<std::int64_t>("/geodesic/sources").data)
      m.geodesic_sources.push_back(static_cast<int>(s));
    const auto d = f.read<float>("/geodesic/distances").data;
    const auto V = static_cast<std::size_t>(m.tmpl.vertices.rows());
    for (std::size_t k = 0; k < m.geodesic_sources.size(); ++k)
      m.geodesic_rows.push_back(
          Eigen::Map<const Eigen::VectorXf>(d.data() + k * V, static_cast<Eigen::Index>(V)));
  }
  try {
    m.initialize();  // the network's shapes; weights, Adam and RNG state come from the file
  } catch (const UsageError& e) {
    throw InvalidInput(e.what(), f.where("/config"));
  }
  m.log = std::move(log);
  m.unprinted = std::move(unprinted);
  m.iteration = nn::read_training_state(f, m.net->store(), *m.adam, m.rng);
  return m;
}

}  // namespace df::models
