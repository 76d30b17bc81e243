#include "models/actgan/model.h"

#include "models/actgan/settings.h"

#include <fmt/format.h>

#include <filesystem>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/provenance.h"
#include "io/file_header.h"
#include "io/schema.h"
#include "models/actgan/settings.h"

namespace df::models {
namespace {

// Every network's parameters, in the file's order.
std::vector<nn::ParameterStore<float>*> stores(const ActganModel& m) {
  return {&m.gen->store(), &m.discriminator_store(), &m.cls->store(), &m.critic->store()};
}

std::unique_ptr<nn::Adam<float>> make_adam(const nn::ParameterStore<float>& s, double lr) {
  nn::AdamOptions o;
  o.lr = lr;
  o.beta1 = 0.5;
  o.beta2 = 0.9;
  return std::make_unique<nn::Adam<float>>(s.size(), o);
}

struct NamedAdam {
  const char* name;
  nn::Adam<float>* adam;
};

std::vector<NamedAdam> optimizers(const ActganModel& m) {
  return {{"decoder", m.adam.decoder.get()}, {"critic", m.adam.critic.get()}, {"gen", m.adam.gen.get()},
          {"disc", m.adam.disc.get()},       {"cls", m.adam.cls.get()}};
}

void write_config(h5::File& f, const ActganModel& m) {
  f.create_groups("/config");
  ActganConfig c = m.config;
  ActganTraining t = m.training;
  t.disc_lr = t.discriminator_lr();  // the rate in use: 0 means --lr
  write_settings(f, "/config", actgan_settings(c, t));
  f.set_attr("/config", "frame_rate", m.frame_rate);
  f.set_attr("/config", "length", m.length);
  f.set_attr("/config", "data", m.data);
}

void read_config(const h5::File& f, ActganModel& m) {
  // Files written before a setting existed read as its default, the model they describe.
  read_settings(f, "/config", actgan_settings(m.config, m.training));
  if (f.exists("/validation/subjects"))  // absent: none (and in files older than it)
    m.training.validation_subjects = f.read<std::int32_t>("/validation/subjects").data;
  m.frame_rate = f.attr_double("/config", "frame_rate");
  m.length = static_cast<int>(f.attr_int("/config", "length"));
  m.data = f.attr_string("/config", "data");
}

}  // namespace

std::vector<std::string> ActganModel::loss_columns() { return {"loss", "disc", "adv", "smooth", "cycle", "gp"}; }

std::vector<std::string> ActganModel::validation_columns() { return {"val_mmd_avg", "val_mmd_seq", "val_mmd_motion_avg", "val_mmd_motion_seq"}; }

std::vector<std::string> ActganModel::log_columns() const {
  std::vector<std::string> c{"iteration"};
  for (auto&& part : {loss_columns(), training.validation_subjects.empty() ? std::vector<std::string>{} : validation_columns()})
    c.insert(c.end(), part.begin(), part.end());
  return c;
}

nn::ParameterStore<float>& ActganModel::discriminator_store() const {
  if (clip_critic) return clip_critic->store();
  if (!disc) throw Error("internal: an ActGAN model without a discriminator");
  return disc->store();
}

void ActganModel::initialize() {
  Rng init(training.seed, 0);
  gen = std::make_unique<ActganGenerator<float>>(config, init);
  disc.reset();
  clip_critic.reset();
  if (config.discriminator == "critic")
    clip_critic = std::make_unique<Critic<float>>(config, Eigen::Index{length} * config.pose, "disc", init);
  else
    disc = make_discriminator<float>(config, length, init);
  cls = std::make_unique<SequenceNet<float>>(config, config.pose, config.classes, "cls", init);
  critic = std::make_unique<Critic<float>>(config, config.pose, "critic", init);
  adam.decoder = make_adam(gen->store(), training.lr_pretrain);
  adam.critic = make_adam(critic->store(), training.lr_pretrain);
  adam.gen = make_adam(gen->store(), training.lr);
  adam.disc = make_adam(discriminator_store(), training.discriminator_lr());
  adam.cls = make_adam(cls->store(), training.lr);
  rng = Rng(training.seed, 1);
  iteration = 0;
  log.clear();
  unprinted.clear();
}

void save_actgan_model(const std::string& path, const ActganModel& m,
                       const std::vector<std::string>& inputs, bool force) {
  std::vector<std::filesystem::path> in(inputs.begin(), inputs.end());
  AtomicOutput out(path, AtomicOutput::Kind::file, force, in);
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, path);
    io::write_header(f, "actgan-model", {m.history});
    write_config(f, m);
    f.set_attr("/", "iteration", m.iteration);
    const auto& vs = m.training.validation_subjects;
    if (!vs.empty()) f.write<std::int32_t>("/validation/subjects", vs, {vs.size()});
    std::string order;
    for (const auto* s : stores(m))
      for (std::size_t k = 0; k < s->views().size(); ++k) {
        f.write_matrix("/params/" + s->views()[k].name, s->value(static_cast<int>(k)));
        order += s->views()[k].name + "\n";
      }
    f.set_attr("/params", "order", order);
    for (const auto& [name, a] : optimizers(m)) {
      const std::string g = std::string("/optimizers/") + name;
      const auto n = static_cast<std::size_t>(a->first_moment().size());
      f.write<float>(g + "/m", std::span<const float>(a->first_moment().data(), n), {n});
      f.write<float>(g + "/v", std::span<const float>(a->second_moment().data(), n), {n});
      f.set_attr(g, "step", static_cast<std::int64_t>(a->steps()));
    }
    const auto st = m.rng.state();
    f.write<std::uint64_t>("/rng/state", std::span<const std::uint64_t>(st.data(), st.size()), {4});
    f.set_attr("/rng", "has_spare", static_cast<std::int64_t>(m.rng.has_spare_normal()));
    f.set_attr("/rng", "spare", m.rng.spare_normal());
    f.write_strings("/classes/names", m.class_names);
    f.write<std::int32_t>("/skeleton/parents", m.parents, {m.parents.size()});
    f.write_strings("/skeleton/joint_names", m.joint_names);
    if (m.normalization.present()) {
      const std::vector<std::size_t> shape{m.joint_names.size(), 3};
      f.write<double>("/normalization/mean", m.normalization.mean, shape);
      f.write<double>("/normalization/std", m.normalization.std, shape);
      f.set_attr("/normalization", "root_joint", m.normalization.root_joint);
      f.set_attr("/normalization", "scale", m.normalization.scale);
    }
    const auto cols = m.log_columns();
    if (!m.log.empty()) {
      f.write<double>("/training/log", m.log, {m.log.size() / cols.size(), cols.size()});
      std::string names;
      for (const auto& c : cols) names += (names.empty() ? "" : " ") + c;
      f.set_attr("/training/log", "columns", names);
    }
    if (!m.unprinted.empty()) f.write<double>("/training/unprinted", m.unprinted, {m.unprinted.size()});
  }
  out.commit();
}

ActganModel load_actgan_model(const std::string& path) {
  h5::File f = io::open_input(path, "actgan-model");
  ActganModel m;
  read_config(f, m);
  m.initialize();
  const auto names = provenance::history_lines(f.attr_string("/params", "order"));
  std::size_t k = 0;
  for (auto* s : stores(m)) {
    for (std::size_t i = 0; i < s->views().size(); ++i, ++k) {
      const auto& v = s->views()[i];
      if (k >= names.size() || names[k] != v.name)
        throw InvalidInput(fmt::format("parameter {} is not '{}' (another network configuration?)", k, v.name), path);
      const auto w = f.read_matrix<float>("/params/" + v.name);
      if (w.rows() != v.rows || w.cols() != v.cols)
        throw InvalidInput(fmt::format("parameter '{}' is [{},{}], expected [{},{}]", v.name, w.rows(), w.cols(), v.rows, v.cols),
                           f.where("/params/" + v.name));
      s->value(static_cast<int>(i)) = w;
    }
  }
  for (const auto& [name, a] : optimizers(m)) {
    const std::string g = std::string("/optimizers/") + name;
    const auto mm = f.read<float>(g + "/m").data, vv = f.read<float>(g + "/v").data;
    if (static_cast<Eigen::Index>(mm.size()) != a->first_moment().size() || vv.size() != mm.size())
      throw InvalidInput("optimizer state does not match the parameters", f.where(g));
    a->first_moment() = Eigen::Map<const nn::Vector<float>>(mm.data(), static_cast<Eigen::Index>(mm.size()));
    a->second_moment() = Eigen::Map<const nn::Vector<float>>(vv.data(), static_cast<Eigen::Index>(vv.size()));
    a->set_steps(static_cast<long>(f.attr_int(g, "step")));
  }
  const auto s = f.read<std::uint64_t>("/rng/state").data;
  m.rng.restore({s[0], s[1], s[2], s[3]}, f.attr_int("/rng", "has_spare") != 0, f.attr_double("/rng", "spare"));
  m.iteration = f.attr_int("/", "iteration");
  m.class_names = f.read_strings("/classes/names");
  m.parents = f.read<std::int32_t>("/skeleton/parents").data;
  m.joint_names = f.read_strings("/skeleton/joint_names");
  if (f.exists("/normalization")) {
    m.normalization.root_joint = static_cast<int>(f.attr_int("/normalization", "root_joint"));
    m.normalization.scale = f.attr_double("/normalization", "scale");
    m.normalization.mean = f.read<double>("/normalization/mean").data;
    m.normalization.std = f.read<double>("/normalization/std").data;
  }
  m.log = f.exists("/training/log") ? f.read<double>("/training/log").data : std::vector<double>{};
  m.unprinted = f.exists("/training/unprinted") ? f.read<double>("/training/unprinted").data : std::vector<double>{};
  m.history = f.attr_string("/", "history");
  return m;
}

}  // namespace df::models
