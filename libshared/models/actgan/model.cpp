#include "models/actgan/model.h"

#include <fmt/format.h>

#include <filesystem>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/provenance.h"
#include "io/file_header.h"
#include "io/model_file.h"
#include "io/schema.h"
#include "io/skeleton_file.h"
#include "models/actgan/settings.h"
#include "models/common/checkpoint.h"

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
  return {{"decoder", m.adam.decoder.get()},
          {"critic", m.adam.critic.get()},
          {"gen", m.adam.gen.get()},
          {"disc", m.adam.disc.get()},
          {"cls", m.adam.cls.get()}};
}

void write_config(h5::File& f, const ActganModel& m) {
  f.create_groups(io::model_layout::config);
  write_settings(f, io::model_layout::config, view(actgan_settings(), m.config, m.training));
  f.set_attr(io::model_layout::config, "frame_rate", m.frame_rate);
  f.set_attr(io::model_layout::config, "length", m.length);
  f.set_attr(io::model_layout::config, "data", m.data);
}

void read_config(const h5::File& f, ActganModel& m) {
  // Files written before a setting existed read as its default, the model they describe.
  read_settings(f, io::model_layout::config, bind(actgan_settings(), m.config, m.training));
  if (f.exists(io::model_layout::validation_subjects))  // absent: none (and in files older than it)
    m.training.validation_subjects =
        f.read<std::int32_t>(io::model_layout::validation_subjects).data;
  m.frame_rate = f.attr_double(io::model_layout::config, "frame_rate");
  m.length = static_cast<int>(f.attr_int(io::model_layout::config, "length"));
  m.data = f.attr_string(io::model_layout::config, "data");
}

}  // namespace

std::vector<std::string> ActganModel::loss_columns() {
  return {"loss", "disc", "adv", "smooth", "cycle", "gp"};
}

std::vector<std::string> ActganModel::validation_columns() {
  return {"val_mmd_avg", "val_mmd_seq", "val_mmd_motion_avg", "val_mmd_motion_seq"};
}

std::vector<std::string> ActganModel::log_columns() const {
  std::vector<std::string> c{"iteration"};
  for (auto&& part :
       {loss_columns(),
        training.validation_subjects.empty() ? std::vector<std::string>{} : validation_columns()})
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
  if (config.discriminator == Discriminator::critic)
    clip_critic =
        std::make_unique<Critic<float>>(config, Eigen::Index{length} * config.pose, "disc", init);
  else
    disc = make_discriminator<float>(config, length, init);
  cls = std::make_unique<SequenceNet<float>>(config, config.pose, config.classes, "cls", init);
  critic = std::make_unique<Critic<float>>(config, config.pose, "critic", init);
  ActganOptimizers fresh;
  fresh.decoder = make_adam(gen->store(), training.lr_pretrain);
  fresh.critic = make_adam(critic->store(), training.lr_pretrain);
  fresh.gen = make_adam(gen->store(), training.lr);
  fresh.disc = make_adam(discriminator_store(), training.discriminator_lr());
  fresh.cls = make_adam(cls->store(), training.lr);
  restart(std::move(fresh), training.seed);
}

void save_actgan_model(const std::string& path, const ActganModel& m,
                       const std::vector<std::string>& inputs, bool force) {
  std::vector<std::filesystem::path> in(inputs.begin(), inputs.end());
  AtomicOutput out(path, AtomicOutput::Kind::file, force, in);
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, path);
    io::write_header(f, "actgan-model", {m.history});
    write_config(f, m);
    io::write_iteration(f, m.iteration);
    const auto& vs = m.training.validation_subjects;
    if (!vs.empty()) f.write<std::int32_t>(io::model_layout::validation_subjects, vs, {vs.size()});
    std::vector<std::string> order;
    for (const auto* s : stores(m))
      for (std::size_t k = 0; k < s->views().size(); ++k) {
        order.push_back(s->views()[k].name);
        io::write_param(f, order.back(), s->value(static_cast<int>(k)));
      }
    io::write_param_order(f, order);
    for (const auto& [name, a] : optimizers(m)) {
      const auto n = static_cast<std::size_t>(a->first_moment().size());
      io::write_adam_state(f, io::model_layout::optimizer(name),
                           std::span<const float>(a->first_moment().data(), n),
                           std::span<const float>(a->second_moment().data(), n), a->steps());
    }
    io::write_rng_state(f, {m.rng.state(), m.rng.has_spare_normal(), m.rng.spare_normal()});
    io::write_classes_and_skeleton(f, m.class_names, m.parents, m.joint_names);
    io::write_pose_normalization(f, m.normalization, 3);
    io::write_training_log(f, m.log, m.log_columns(), m.unprinted);
  }
  out.commit();
}

ActganModel load_actgan_model(const std::string& path) {
  h5::File f = io::open_input(path, "actgan-model");
  ActganModel m;
  read_config(f, m);
  m.initialize();
  const auto names = io::read_param_order(f);
  std::size_t k = 0;
  for (auto* s : stores(m)) {
    for (std::size_t i = 0; i < s->views().size(); ++i, ++k) {
      const auto& v = s->views()[i];
      if (k >= names.size() || names[k] != v.name)
        throw InvalidInput(
            fmt::format("parameter {} is not '{}' (another network configuration?)", k, v.name),
            path);
      s->value(static_cast<int>(i)) = io::read_param(f, v.name, v.rows, v.cols);
    }
  }
  for (const auto& [name, a] : optimizers(m))
    restore_adam(*a, io::read_adam_state(f, io::model_layout::optimizer(name),
                                         static_cast<std::size_t>(a->first_moment().size())));
  restore_rng(m.rng, io::read_rng_state(f));
  m.iteration = io::read_iteration(f);
  io::read_classes_and_skeleton(f, m.class_names, m.parents, m.joint_names);
  m.normalization = io::read_pose_normalization(f);
  auto log = io::read_training_log(f);
  m.log = std::move(log.rows);
  m.unprinted = std::move(log.unprinted);
  m.history = io::read_history(f);
  return m;
}

}  // namespace df::models
