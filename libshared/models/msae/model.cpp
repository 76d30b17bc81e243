#include "models/msae/model.h"

#include <fmt/format.h>

#include <cmath>

#include "core/atomic_output.h"
#include "core/error.h"
#include "geometry/mesh_topology.h"
#include "io/file_header.h"
#include "io/schema.h"
#include "models/common/checkpoint.h"
#include "models/common/model_file.h"
#include "models/msae/settings.h"

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
  restart(make_adam(), training.seed);
}

std::unique_ptr<nn::Adam<float>> MsaeModel::make_adam(std::int64_t start) const {
  nn::AdamOptions ao;
  ao.lr = training.lr;
  if (training.separate_rate == SeparateRate::continue_)
    ao.lr *= std::pow(training.lr_decay, static_cast<double>(start) / training.lr_decay_steps);
  ao.schedule = nn::AdamOptions::Schedule::exponential;
  ao.decay_rate = training.lr_decay;
  ao.decay_steps = training.lr_decay_steps;
  ao.warmup_steps = training.lr_warmup;
  if (training.started_rate != 1) {
    const auto& views = net->store().views();
    for (const auto& b : net->blocks())
      if (b.level < config.started_levels())
        for (int p : b.parameters()) {
          const auto& v = views[static_cast<std::size_t>(p)];
          ao.scaled.push_back({v.offset, v.rows * v.cols, training.started_rate});
        }
  }
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
    f.create_groups(io::model_layout::config);
    write_settings(f, io::model_layout::config, view(msae_settings(), m.config, m.training));
    write_mesh_model_common(f, m.tmpl, m.normalization, m.log, m.log_columns(), m.unprinted);
    if (m.collapse_since > 0) {  // the log has a row
      f.set_attr(io::model_layout::training_log, "collapse", m.collapse);
      f.set_attr(io::model_layout::training_log, "collapse_since", m.collapse_since);
    }
    f.create_groups(io::model_layout::split);
    f.set_attr(io::model_layout::split, "data", m.split.data);
    write_frames(f, io::model_layout::split_part("train"), m.split.train);
    write_frames(f, io::model_layout::split_part("validation"), m.split.validation);
    write_frames(f, io::model_layout::split_part("test"), m.split.test);
    f.create_groups(io::model_layout::geodesic);
    f.set_attr(io::model_layout::geodesic, "method", std::string(name_of(m.geodesic_method)));
    f.set_attr(io::model_layout::geodesic, "diameter", m.geodesic_diameter);
    if (!m.geodesic_sources.empty()) {
      const std::vector<std::int64_t> sources(m.geodesic_sources.begin(), m.geodesic_sources.end());
      f.write<std::int64_t>(io::model_layout::geodesic_part("sources"), sources, {sources.size()});
      const auto V = static_cast<std::size_t>(m.tmpl.vertices.rows());
      std::vector<float> rows;
      for (const auto& r : m.geodesic_rows) rows.insert(rows.end(), r.data(), r.data() + r.size());
      f.write<float>(io::model_layout::geodesic_part("distances"), rows, {sources.size(), V});
    }
    write_training_state(f, m.net->store(), m.adam.get(), m.rng, m.iteration);
    f.close();
  }
  out.commit();
}

MsaeModel load_msae_model(const std::string& path) {
  h5::File f = io::open_input(path, "msae-model");
  MsaeModel m;
  m.history = io::read_history(f);
  // Files written before a setting existed read as its default, the network they describe.
  read_settings(f, io::model_layout::config, bind(msae_settings(), m.config, m.training));
  if (m.config.kz.empty() || m.config.kz.size() != m.config.d.size())
    throw InvalidInput("kz and d must have one value per level", f.where(io::model_layout::config));
  std::vector<double> log, unprinted;
  read_mesh_model_common(f, m.tmpl, m.normalization, log, unprinted);
  m.log_validation_erms =
      f.exists(io::model_layout::training_log) &&
      f.attr_string(io::model_layout::training_log, "columns").find("validation_erms") !=
          std::string::npos;
  if (f.exists(io::model_layout::training_log) &&
      f.has_attr(io::model_layout::training_log, "collapse_since")) {
    m.collapse = f.attr_string(io::model_layout::training_log, "collapse");
    m.collapse_since = f.attr_int(io::model_layout::training_log, "collapse_since");
  }
  m.split.data = f.attr_string(io::model_layout::split, "data");
  m.split.train = f.read<std::int64_t>(io::model_layout::split_part("train")).data;
  m.split.validation = f.read<std::int64_t>(io::model_layout::split_part("validation")).data;
  m.split.test = f.read<std::int64_t>(io::model_layout::split_part("test")).data;
  m.geodesic_diameter = f.attr_double(io::model_layout::geodesic, "diameter");
  try {
    m.geodesic_method = parse_choice<GeodesicMethod>(
        f.attr_string(io::model_layout::geodesic, "method"), "the method");
  } catch (const UsageError& e) {
    throw InvalidInput(e.what(), f.where(io::model_layout::geodesic));
  }
  if (f.exists(io::model_layout::geodesic_part("sources"))) {
    for (auto s : f.read<std::int64_t>(io::model_layout::geodesic_part("sources")).data)
      m.geodesic_sources.push_back(static_cast<int>(s));
    const auto d = f.read<float>(io::model_layout::geodesic_part("distances")).data;
    const auto V = static_cast<std::size_t>(m.tmpl.vertices.rows());
    for (std::size_t k = 0; k < m.geodesic_sources.size(); ++k)
      m.geodesic_rows.push_back(
          Eigen::Map<const Eigen::VectorXf>(d.data() + k * V, static_cast<Eigen::Index>(V)));
  }
  try {
    m.initialize();  // the network's shapes; weights, Adam and RNG state come from the file
  } catch (const UsageError& e) {
    throw InvalidInput(e.what(), f.where(io::model_layout::config));
  }
  m.log = std::move(log);
  m.unprinted = std::move(unprinted);
  m.iteration = read_training_state(f, m.net->store(), *m.adam, m.rng);
  return m;
}

}  // namespace df::models
