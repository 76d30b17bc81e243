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

std::vector<std::string> BdlstmModel::log_columns() const {
  std::vector<std::string> c{"iteration", "total", "recon", "bidir", "kl", "l2"};
  if (training.validation_fraction > 0) c.push_back("validation");
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
    std::vector<std::int64_t> validation;
    for (std::size_t k = 0; k < s; ++k)
      validation.insert(validation.end(), {m.split.validation_begin[k], m.split.validation_end[k]});
    f.write<std::int64_t>(io::model_layout::split_part("validation"), validation, {s, 2});
    write_training_state(f, m.net->store(), kind == BdlstmFile::checkpoint ? m.adam.get() : nullptr,
                         m.rng, m.iteration);
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
  // Added later: absent means no validation part (an empty range per sequence).
  const auto validation =
      f.exists(io::model_layout::split_part("validation"))
          ? f.read<std::int64_t>(io::model_layout::split_part("validation")).data
          : std::vector<std::int64_t>{};
  for (std::size_t k = 0; k < m.split.sequences.size(); ++k) {
    m.split.validation_begin.push_back(validation.empty() ? m.split.train_begin[k]
                                                          : validation[2 * k]);
    m.split.validation_end.push_back(validation.empty() ? m.split.train_begin[k]
                                                        : validation[2 * k + 1]);
  }
  m.initialize();          // the network's shapes; weights, Adam and RNG state come from the file
  m.log = std::move(log);  // after initialize(), which clears it
  m.unprinted = std::move(unprinted);
  m.iteration = read_training_state(f, m.net->store(), *m.adam, m.rng);
  m.optimizer_state = has_optimizer_state(f);
  return m;
}

}  // namespace df::models
