#include <CLI/CLI.hpp>
#include <catch2/catch.hpp>
#include <set>

#include "../../helpers.h"
#include "io/schema.h"
#include "models/actgan/settings.h"
#include "models/bdlstm/settings.h"
#include "models/common/settings.h"
#include "models/msae/settings.h"

using namespace df;
using namespace df::models;

namespace {

// A network's settings and a run's, as a model has them (ToyNet, ToyRun), in one table.
struct ToyNet {
  std::vector<int> kz = {10, 5};
  std::vector<double> d = {0.4, 0.2};
  bool attention = true, separate = false;
  std::string latent = "linear";
};
struct ToyRun {
  double lr = 1e-3;
  int batch = 256;
  std::int64_t iterations = 2000;
  std::uint64_t seed = 0;
  double added_later = 0.5;
};
struct Toy {
  ToyNet net;
  ToyRun run;
};

const SettingsTable<ToyNet, ToyRun>& toy_table() {
  using N = ToyNet;
  using R = ToyRun;
  static const SettingsTable<ToyNet, ToyRun> rows = {
      {.name = "kz", .target = &N::kz, .help = "per level"},
      {.name = "d", .target = &N::d, .help = "radius per level"},
      {.name = "attention", .target = &N::attention, .help = "off", .option = "--no-attention"},
      {.name = "separate", .target = &N::separate, .help = "level by level"},
      {.name = "latent", .target = &N::latent, .help = "codes", .choices = {"tanh", "linear"}},
      {.name = "lr", .target = &R::lr, .help = "rate"},
      {.name = "batch", .target = &R::batch, .help = "shapes"},
      {.name = "iterations", .target = &R::iterations, .help = "count", .resume = false},
      {.name = "seed", .target = &R::seed},
      {.name = "added_later", .target = &R::added_later, .help = "new", .optional = true}};
  return rows;
}
Settings toy_settings(Toy& t) {
  return bind(toy_table(), t.net, t.run);
}
// A const toy is read through the table where it is: no copy is made to write or compare it.
SettingViews toy_view(const Toy& t) {
  return view(toy_table(), t.net, t.run);
}

}  // namespace

TEST_CASE("settings: one table gives the command line", "[models][settings]") {
  Toy t;
  CLI::App app;
  add_settings(*app.add_option_group("Toy"), toy_settings(t));
  std::vector<std::string> args = {"--no-attention", "--separate", "--kz", "3,2",
                                   "--latent",       "tanh",       "--lr", "0.01",
                                   "--added-later",  "2"};
  std::reverse(args.begin(), args.end());
  app.parse(args);
  CHECK(!t.net.attention);
  CHECK(t.net.separate);
  CHECK(t.net.kz == std::vector<int>{3, 2});
  CHECK(t.net.latent == "tanh");
  CHECK(t.run.lr == 0.01);
  CHECK(t.run.added_later == 2);
  CHECK(t.run.seed == 0);  // no help: not an option
  Toy u;
  CLI::App bad;
  add_settings(*bad.add_option_group("Toy"), toy_settings(u));
  std::vector<std::string> wrong = {"elu", "--latent"};
  CHECK_THROWS_AS(bad.parse(wrong), CLI::ValidationError);
  CHECK_THROWS(bad.parse(std::vector<std::string>{"1", "--seed"}));
}

TEST_CASE("settings: the model file's /config round trip, old files, the resume check",
          "[models][settings]") {
  test::TempDir dir;
  Toy a;
  a.net.kz = {7, 3, 2};
  a.net.attention = false;
  a.run.seed = 18446744073709551615ull;  // the 64-bit seed survives as text
  a.run.iterations = 12345;
  {
    h5::File f(dir / "m.h5", h5::File::Mode::create);
    f.create_groups("/config");
    write_settings(f, "/config", toy_view(a));
    CHECK(f.attr_int("/config", "attention") == 0);
    CHECK(f.attr_string("/config", "seed") == "18446744073709551615");
    CHECK(f.attr_doubles("/config", "kz") == std::vector<double>{7, 3, 2});
  }
  Toy b;
  {
    const h5::File f(dir / "m.h5", h5::File::Mode::read);
    read_settings(f, "/config", toy_settings(b));
  }
  CHECK(b.net.kz == a.net.kz);
  CHECK(!b.net.attention);
  CHECK(b.run.seed == a.run.seed);
  CHECK(b.run.iterations == 12345);

  // A file written before a setting existed: an optional one keeps its default, a required one
  // is refused with the file and group named.
  {
    h5::File f(dir / "old.h5", h5::File::Mode::create);
    f.create_groups("/config");
    SettingViews s = toy_view(a);
    s.pop_back();  // no added_later
    write_settings(f, "/config", s);
  }
  Toy c;
  c.run.added_later = 0.25;
  {
    const h5::File f(dir / "old.h5", h5::File::Mode::read);
    read_settings(f, "/config", toy_settings(c));
    CHECK(c.run.added_later == 0.25);
    Settings strict = toy_settings(c);
    strict.back().optional = false;
    const std::string msg = test::error_message([&] { read_settings(f, "/config", strict); });
    CHECK_THAT(msg, Catch::Contains("lacks the setting added_later"));
    CHECK_THAT(msg, Catch::Contains("old.h5"));
  }

  // Resuming: a resume setting that differs is refused, naming its option and both values; one
  // that may change (the iteration count a run goes on to) is not.
  Toy d = b;
  d.run.iterations = 99999;
  CHECK_NOTHROW(require_same_settings(toy_view(b), toy_view(d), "ck.h5"));
  d.net.kz = {7, 3};
  const std::string msg =
      test::error_message([&] { require_same_settings(toy_view(b), toy_view(d), "ck.h5"); });
  CHECK_THAT(msg, Catch::Contains("made with --kz 7,3,2, this run has 7,3"));
  CHECK_THAT(msg, Catch::Contains("ck.h5"));
  // A flag is named as the flag, whichever way its field reads.
  Toy e = b;
  e.net.kz = b.net.kz;
  e.net.attention = !b.net.attention;  // b was made with --no-attention
  CHECK_THAT(test::error_message([&] { require_same_settings(toy_view(b), toy_view(e), "ck.h5"); }),
             Catch::Contains("made with --no-attention, this run does not"));
  Toy g = b;
  g.net.separate = true;  // b was made without --separate
  CHECK_THAT(test::error_message([&] { require_same_settings(toy_view(b), toy_view(g), "ck.h5"); }),
             Catch::Contains("made without --separate, this run gives it"));
}

namespace {
std::set<std::string> config_attributes(const std::string& kind) {
  std::set<std::string> names;
  for (const auto& object : io::schema(kind).doc.at("objects"))
    if (object.at("path") == "/config")
      for (const auto& a : object.at("attributes")) names.insert(a.at("name").get<std::string>());
  return names;
}
template <class C, class T>
std::set<std::string> table_names(const SettingsTable<C, T>& settings) {
  std::set<std::string> names;
  for (const auto& s : settings) CHECK(names.insert(s.name).second);  // each declared once
  return names;
}
}  // namespace

TEST_CASE("settings: each model's table is its schema's /config", "[models][settings]") {
  CHECK(table_names(msae_settings()) == config_attributes("msae-model"));
  CHECK(table_names(bdlstm_settings()) == config_attributes("bdlstm-model"));
  auto actgan = table_names(actgan_settings());
  for (const char* of_the_data : {"frame_rate", "length", "data"})
    CHECK(actgan.insert(of_the_data).second);
  CHECK(actgan == config_attributes("actgan-model"));
}

TEST_CASE("settings: a flag sets its field, a named option clears it", "[models][settings]") {
  ActganConfig c;
  ActganTraining t;
  CLI::App app;
  add_settings(*app.add_option_group("Losses"), bind(actgan_loss_settings(), c, t));
  add_settings(*app.add_option_group("Training"), bind(actgan_training_settings(), c, t));
  app.parse(std::vector<std::string>{"--classifier-only", "--freeze-decoder", "--direct-latent"});
  CHECK(!c.residual);        // --direct-latent clears residual
  CHECK(c.classifier);       // not given
  CHECK(!t.train_decoder);   // --freeze-decoder clears train_decoder
  CHECK(t.classifier_only);  // --classifier-only sets it
}

TEST_CASE("settings: an enum held as text", "[models][settings]") {
  BdlstmConfig c;
  BdlstmTraining t;
  CLI::App app;
  add_settings(*app.add_option_group("Network"), bind(bdlstm_network_settings(), c, t));
  app.parse(std::vector<std::string>{"unidirectional", "--directions", "--no-kl"});
  CHECK(c.directions == Directions::unidirectional);
  CHECK(!c.kl);
  CHECK(c.l2);
  test::TempDir dir;
  {
    h5::File f(dir / "m.h5", h5::File::Mode::create);
    f.create_groups("/config");
    write_settings(f, "/config", view(bdlstm_settings(), c, t));
    CHECK(f.attr_string("/config", "directions") == "unidirectional");
    f.set_attr("/config", "directions", std::string("sideways"));
  }
  BdlstmConfig back;
  const h5::File f(dir / "m.h5", h5::File::Mode::read);
  const std::string msg =
      test::error_message([&] { read_settings(f, "/config", bind(bdlstm_settings(), back, t)); });
  CHECK_THAT(msg, Catch::Contains("sideways"));
  CHECK_THAT(msg, Catch::Contains("m.h5"));
}

TEST_CASE("settings: a typed mode is read, written and offered by its names",
          "[models][settings]") {
  // One list per enum: its names parse, print (fmt too) and are the command line's choices.
  CHECK(parse_choice<Support>("proximal", "--support") == Support::proximal);
  CHECK(name_of(MsaeInit::local_all) == "local-all");
  CHECK(fmt::format("{}", Support::hard) == "hard");
  CHECK(choice_names<TestPart>() == std::vector<std::string>{"end", "start", "middle", "random"});
  CHECK_THAT(test::error_message([] { parse_choice<Support>("firm", "--support"); }),
             Catch::Contains("--support must be one of soft, proximal, hard, not 'firm'"));
  MsaeConfig c;
  MsaeTraining t;
  CLI::App app;
  add_settings(*app.add_option_group("Network"), bind(msae_settings(), c, t));
  app.parse(std::vector<std::string>{"local-all", "--init", "hard", "--support"});
  CHECK(c.support == Support::hard);
  CHECK(c.init == MsaeInit::local_all);
  CHECK_THAT(app.help(), Catch::Contains("local-all"));
  MsaeConfig d;
  CLI::App bad;
  add_settings(*bad.add_option_group("Network"), bind(msae_settings(), d, t));
  CHECK_THROWS_AS(bad.parse(std::vector<std::string>{"firm", "--support"}), CLI::ValidationError);
  // --split offers only what a user chooses; "lists" (--train/--test) is written and read.
  CHECK_THROWS_AS(bad.parse(std::vector<std::string>{"lists", "--split"}), CLI::ValidationError);
  test::TempDir dir;
  t.split = SplitKind::lists;
  {
    h5::File f(dir / "m.h5", h5::File::Mode::create);
    f.create_groups("/config");
    write_settings(f, "/config", view(msae_settings(), c, t));
    CHECK(f.attr_string("/config", "support") == "hard");
    CHECK(f.attr_string("/config", "split") == "lists");
    f.set_attr("/config", "init", std::string("uniform"));
  }
  MsaeConfig back;
  MsaeTraining back_t;
  const h5::File f(dir / "m.h5", h5::File::Mode::read);
  const std::string msg = test::error_message(
      [&] { read_settings(f, "/config", bind(msae_settings(), back, back_t)); });
  CHECK_THAT(msg, Catch::Contains("init: the value must be one of glorot, normal, small, local, "
                                  "local-all, not 'uniform'"));
  CHECK_THAT(msg, Catch::Contains("m.h5"));
}

TEST_CASE("settings: ranges in the table are the trainers' option checks", "[models][settings]") {
  CHECK(positive().text() == "positive");
  CHECK(at_least(0).text() == "not negative");
  CHECK(at_least(2).text() == "at least 2");
  CHECK(within(0, 1, true).text() == "in (0, 1]");
  CHECK(within(0, 1, false, true).text() == "in [0, 1)");
  CHECK(within(0, 1, true).holds(1));
  CHECK(!within(0, 1, true).holds(0));
  CHECK(!within(0, 1, false, true).holds(1));
  MsaeConfig c;
  MsaeTraining t;
  CHECK_NOTHROW(check_ranges(view(msae_settings(), c, t)));  // the defaults lie inside
  t.lr = 0;
  CHECK_THAT(test::error_message([&] { check_ranges(view(msae_settings(), c, t)); }),
             Catch::Contains("--lr must be positive (got 0)"));
  t.lr = 1e-3;
  c.d = {0.4, 1.5};  // every number of a list
  CHECK_THAT(test::error_message([&] { check_ranges(view(msae_settings(), c, t)); }),
             Catch::Contains("--d must be in (0, 1] (got 0.4,1.5)"));
  BdlstmConfig bc;
  BdlstmTraining bt;
  CHECK_NOTHROW(check_ranges(view(bdlstm_settings(), bc, bt)));
  bt.window = 1;
  CHECK_THROWS_AS(check_ranges(view(bdlstm_settings(), bc, bt)), UsageError);
  ActganConfig ac;
  ActganTraining at;
  CHECK_NOTHROW(check_ranges(view(actgan_settings(), ac, at)));
  at.batch = 1;
  CHECK_THAT(test::error_message([&] { check_ranges(view(actgan_settings(), ac, at)); }),
             Catch::Contains("--batch must be at least 2 (got 1)"));
}
