#include "models/bdlstm/model.h"

#include <fmt/format.h>

#include "core/atomic_output.h"
#include "core/error.h"
#include "geometry/mesh_topology.h"
#include "io/file_header.h"
#include "io/schema.h"
#include "models/bdlstm/settings.h"
#include "models/common/checkpoint.h"
#include "models/common/model_file.h"

namespace df::models {
namespace {

// Early stopping's record (train-bdlstm --stopping-fraction): which loss line's weights the
// model file holds; a checkpoint adds those weights (it holds the last ones as its parameters).
constexpr const char* kBest = "/training/best";
constexpr const char* kBestWeights = "/training/best/weights";

// The [begin, end) range of each sequence's part, as /split/<part> stores it ([S, 2]).
void write_part(h5::File& f, const char* part, const std::vector<std::int64_t>& begin,
                const std::vector<std::int64_t>& end) {
  std::vector<std::int64_t> ranges;
  for (std::size_t k = 0; k < begin.size(); ++k) ranges.insert(ranges.end(), {begin[k], end[k]});
  f.write<std::int64_t>(io::model_layout::split_part(part), ranges, {begin.size(), 2});
}
// Added later (validation, stopping): absent means an empty range per sequence.
void read_part(const h5::File& f, const char* part, const BdlstmSplit& split,
               std::vector<std::int64_t>& begin, std::vector<std::int64_t>& end) {
  const auto ranges = f.exists(io::model_layout::split_part(part))
                          ? f.read<std::int64_t>(io::model_layout::split_part(part)).data
                          : std::vector<std::int64_t>{};
  for (std::size_t k = 0; k < split.sequences.size(); ++k) {
    begin.push_back(ranges.empty() ? split.train_begin[k] : ranges[2 * k]);
    end.push_back(ranges.empty() ? split.train_begin[k] : ranges[2 * k + 1]);
  }
}

}  // namespace

std::vector<std::string> BdlstmModel::log_columns() const {
  std::vector<std::string> c{"iteration", "total", "recon", "bidir", "kl", "l2"};
  if (training.validation_fraction > 0) c.push_back("validation");
  if (training.stopping_fraction > 0) c.push_back("stopping");
  return c;
}

void BdlstmModel::initialize() {
  auto topo = geometry::mesh_topology(tmpl.faces, static_cast<int>(tmpl.vertices.rows()));
  net = std::make_unique<BdlstmNet<float>>(config, static_cast<int>(tmpl.vertices.rows()),
                                           topo.edges, training.seed);
  nn::AdamOptions ao;
  ao.lr = training.lr;
  restart(std::make_unique<nn::Adam<float>>(net->store().size(), ao), training.seed);
}

void save_bdlstm_model(const std::string& path, const BdlstmModel& m,
                       const std::vector<std::string>& inputs, bool force, BdlstmFile kind) {
  std::vector<std::filesystem::path> in(inputs.begin(), inputs.end());
  AtomicOutput out(path, AtomicOutput::Kind::file, force, in);
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, path);
    io::write_header(f, "bdlstm-model", {m.history});
    f.create_groups(io::model_layout::config);
    write_settings(f, io::model_layout::config, view(bdlstm_settings(), m.config, m.training));
    write_mesh_model_common(f, m.tmpl, m.normalization, m.log, m.log_columns(), m.unprinted);
    if (!m.log.empty() && m.kl_per_frame >= 0) {
      f.set_attr(io::model_layout::training_log, "kl_per_frame", m.kl_per_frame);
      f.set_attr(io::model_layout::training_log, "latent_collapsed",
                 static_cast<int>(m.latent_collapsed));
    }
    const std::size_t s = m.split.sequences.size();
    f.create_groups(io::model_layout::split);
    f.set_attr(io::model_layout::split, "data", m.split.data);
    f.write_strings(io::model_layout::split_part("sequences"), m.split.sequences);
    std::vector<std::int64_t> train, test;
    for (std::size_t k = 0; k < s; ++k) {
      train.insert(train.end(), {m.split.train_begin[k], m.split.train_end[k]});
      test.insert(test.end(), {m.split.test_begin[k], m.split.test_end[k]});
    }
    f.write<std::int64_t>(io::model_layout::split_part("train"), train, {s, 2});
    f.write<std::int64_t>(io::model_layout::split_part("test"), test, {s, 2});
    write_part(f, "validation", m.split.validation_begin, m.split.validation_end);
    if (m.training.stopping_fraction > 0)
      write_part(f, "stopping", m.split.stopping_begin, m.split.stopping_end);
    write_training_state(f, m.net->store(), kind == BdlstmFile::checkpoint ? m.adam.get() : nullptr,
                         m.rng, m.iteration);
    if (m.best_weights.size() > 0) {
      f.create_groups(kBest);
      f.set_attr(kBest, "iteration", m.best_iteration);
      f.set_attr(kBest, "stopping", m.best_stopping);
      if (kind == BdlstmFile::checkpoint)
        f.write<float>(kBestWeights,
                       std::vector<float>(m.best_weights.data(),
                                          m.best_weights.data() + m.best_weights.size()),
                       {static_cast<std::size_t>(m.best_weights.size())});
    }
    f.close();
  }
  out.commit();
}

BdlstmModel load_bdlstm_model(const std::string& path) {
  h5::File f = io::open_input(path, "bdlstm-model");
  BdlstmModel m;
  m.history = io::read_history(f);
  // Files written before a setting existed read as the structs' default, the paper's form (the
  // tool's learning defaults are applied by train-bdlstm, not here).
  read_settings(f, io::model_layout::config, bind(bdlstm_settings(), m.config, m.training));
  std::vector<double> log, unprinted;
  read_mesh_model_common(f, m.tmpl, m.normalization, log, unprinted);
  if (f.exists(io::model_layout::training_log) &&
      f.has_attr(io::model_layout::training_log, "kl_per_frame")) {
    m.kl_per_frame = f.attr_double(io::model_layout::training_log, "kl_per_frame");
    m.latent_collapsed = f.attr_int(io::model_layout::training_log, "latent_collapsed") != 0;
  }
  m.split.data = f.attr_string(io::model_layout::split, "data");
  m.split.sequences = f.read_strings(io::model_layout::split_part("sequences"));
  auto train = f.read<std::int64_t>(io::model_layout::split_part("train")).data,
       test = f.read<std::int64_t>(io::model_layout::split_part("test")).data;
  for (std::size_t k = 0; k < m.split.sequences.size(); ++k) {
    m.split.train_begin.push_back(train[2 * k]);
    m.split.train_end.push_back(train[2 * k + 1]);
    m.split.test_begin.push_back(test[2 * k]);
    m.split.test_end.push_back(test[2 * k + 1]);
  }
  read_part(f, "validation", m.split, m.split.validation_begin, m.split.validation_end);
  read_part(f, "stopping", m.split, m.split.stopping_begin, m.split.stopping_end);
  m.initialize();          // the network's shapes; weights, Adam and RNG state come from the file
  m.log = std::move(log);  // after initialize(), which clears it
  m.unprinted = std::move(unprinted);
  m.iteration = read_training_state(f, m.net->store(), *m.adam, m.rng);
  m.optimizer_state = has_optimizer_state(f);
  if (f.exists(kBest)) {
    m.best_iteration = f.attr_int(kBest, "iteration");
    m.best_stopping = f.attr_double(kBest, "stopping");
    if (f.exists(kBestWeights)) {
      const auto w = f.read<float>(kBestWeights).data;
      if (static_cast<Eigen::Index>(w.size()) != m.net->store().values().size())
        throw InvalidInput("the early-stopping weights do not match the network's parameters",
                           path);
      m.best_weights = Eigen::Map<const nn::Vector<float>>(w.data(), std::ssize(w));
    }
  }
  return m;
}

}  // namespace df::models
