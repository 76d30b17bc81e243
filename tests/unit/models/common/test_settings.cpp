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

struct Toy {
  std::vector<int> kz = {10, 5};
  std::vector<double> d = {0.4, 0.2};
  bool attention = true, separate = false;
  std::string latent = "linear";
  double lr = 1e-3;
  int batch = 256;
  std::int64_t iterations = 2000;
  std::uint64_t seed = 0;
  double added_later = 0.5;
};

Settings toy_settings(Toy& t) {
  return {{.name = "kz", .target = &t.kz, .help = "per level"},
          {.name = "d", .target = &t.d, .help = "radius per level"},
          {.name = "attention", .target = &t.attention, .help = "off", .option = "--no-attention"},
          {.name = "separate", .target = &t.separate, .help = "level by level"},
          {.name = "latent", .target = &t.latent, .help = "codes", .choices = {"tanh", "linear"}},
          {.name = "lr", .target = &t.lr, .help = "rate"},
          {.name = "batch", .target = &t.batch, .help = "shapes"},
          {.name = "iterations", .target = &t.iterations, .help = "count", .resume = false},
          {.name = "seed", .target = &t.seed},
          {.name = "added_later", .target = &t.added_later, .help = "new", .optional = true}};
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
  CHECK(!t.attention);
  CHECK(t.separate);
  CHECK(t.kz == std::vector<int>{3, 2});
  CHECK(t.latent == "tanh");
  CHECK(t.lr == 0.01);
  CHECK(t.added_later == 2);
  CHECK(t.seed == 0);  // no help: not an option
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
  a.kz = {7, 3, 2};
  a.attention = false;
  a.seed = 18446744073709551615ull;  // the 64-bit seed survives as text
  a.iterations = 12345;
  {
    h5::File f(dir / "m.h5", h5::File::Mode::create);
    f.create_groups("/config");
    write_settings(f, "/config", toy_settings(a));
    CHECK(f.attr_int("/config", "attention") == 0);
    CHECK(f.attr_string("/config", "seed") == "18446744073709551615");
    CHECK(f.attr_doubles("/config", "kz") == std::vector<double>{7, 3, 2});
  }
  Toy b;
  {
    const h5::File f(dir / "m.h5", h5::File::Mode::read);
    read_settings(f, "/config", toy_settings(b));
  }
  CHECK(b.kz == a.kz);
  CHECK(!b.attention);
  CHECK(b.seed == a.seed);
  CHECK(b.iterations == 12345);

  // A file written before a setting existed: an optional one keeps its default, a required one
  // is refused with the file and group named.
  {
    h5::File f(dir / "old.h5", h5::File::Mode::create);
    f.create_groups("/config");
    Settings s = toy_settings(a);
    s.pop_back();  // no added_later
    write_settings(f, "/config", s);
  }
  Toy c;
  c.added_later = 0.25;
  {
    const h5::File f(dir / "old.h5", h5::File::Mode::read);
    read_settings(f, "/config", toy_settings(c));
    CHECK(c.added_later == 0.25);
    Settings strict = toy_settings(c);
    strict.back().optional = false;
    const std::string msg = test::error_message([&] { read_settings(f, "/config", strict); });
    CHECK_THAT(msg, Catch::Contains("lacks the setting added_later"));
    CHECK_THAT(msg, Catch::Contains("old.h5"));
  }

  // Resuming: a resume setting that differs is refused, naming its option and both values; one
  // that may change (the iteration count a run goes on to) is not.
  Toy d = b;
  d.iterations = 99999;
  CHECK_NOTHROW(require_same_settings(toy_settings(b), toy_settings(d), "ck.h5"));
  d.kz = {7, 3};
  const std::string msg = test::error_message(
      [&] { require_same_settings(toy_settings(b), toy_settings(d), "ck.h5"); });
  CHECK_THAT(msg, Catch::Contains("made with --kz 7,3,2, this run has 7,3"));
  CHECK_THAT(msg, Catch::Contains("ck.h5"));
  // A flag is named as the flag, whichever way its field reads.
  Toy e = b;
  e.kz = b.kz;
  e.attention = !b.attention;  // b was made with --no-attention
  CHECK_THAT(test::error_message(
                 [&] { require_same_settings(toy_settings(b), toy_settings(e), "ck.h5"); }),
             Catch::Contains("made with --no-attention, this run does not"));
  Toy g = b;
  g.separate = true;  // b was made without --separate
  CHECK_THAT(test::error_message(
                 [&] { require_same_settings(toy_settings(b), toy_settings(g), "ck.h5"); }),
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
std::set<std::string> table_names(const Settings& settings) {
  std::set<std::string> names;
  for (const Setting& s : settings) CHECK(names.insert(s.name).second);  // each declared once
  return names;
}
}  // namespace

TEST_CASE("settings: each model's table is its schema's /config", "[models][settings]") {
  MsaeConfig mc;
  MsaeTraining mt;
  CHECK(table_names(msae_settings(mc, mt)) == config_attributes("msae-model"));
  BdlstmConfig bc;
  BdlstmTraining bt;
  CHECK(table_names(bdlstm_settings(bc, bt)) == config_attributes("bdlstm-model"));
  ActganConfig ac;
  ActganTraining at;
  auto actgan = table_names(actgan_settings(ac, at));
  for (const char* of_the_data : {"frame_rate", "length", "data"})
    CHECK(actgan.insert(of_the_data).second);
  CHECK(actgan == config_attributes("actgan-model"));
}

TEST_CASE("settings: a flag sets its field, a named option clears it", "[models][settings]") {
  ActganConfig c;
  ActganTraining t;
  CLI::App app;
  add_settings(*app.add_option_group("Losses"), actgan_loss_settings(c));
  add_settings(*app.add_option_group("Training"), actgan_training_settings(t));
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
  add_settings(*app.add_option_group("Network"), bdlstm_network_settings(c));
  app.parse(std::vector<std::string>{"unidirectional", "--directions", "--no-kl"});
  CHECK(c.directions == Directions::unidirectional);
  CHECK(!c.kl);
  CHECK(c.l2);
  test::TempDir dir;
  {
    h5::File f(dir / "m.h5", h5::File::Mode::create);
    f.create_groups("/config");
    write_settings(f, "/config", bdlstm_settings(c, t));
    CHECK(f.attr_string("/config", "directions") == "unidirectional");
    f.set_attr("/config", "directions", std::string("sideways"));
  }
  BdlstmConfig back;
  const h5::File f(dir / "m.h5", h5::File::Mode::read);
  const std::string msg =
      test::error_message([&] { read_settings(f, "/config", bdlstm_settings(back, t)); });
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
  add_settings(*app.add_option_group("Network"), msae_settings(c, t));
  app.parse(std::vector<std::string>{"local-all", "--init", "hard", "--support"});
  CHECK(c.support == Support::hard);
  CHECK(c.init == MsaeInit::local_all);
  CHECK_THAT(app.help(), Catch::Contains("local-all"));
  MsaeConfig d;
  CLI::App bad;
  add_settings(*bad.add_option_group("Network"), msae_settings(d, t));
  CHECK_THROWS_AS(bad.parse(std::vector<std::string>{"firm", "--support"}), CLI::ValidationError);
  // --split offers only what a user chooses; "lists" (--train/--test) is written and read.
  CHECK_THROWS_AS(bad.parse(std::vector<std::string>{"lists", "--split"}), CLI::ValidationError);
  test::TempDir dir;
  t.split = SplitKind::lists;
  {
    h5::File f(dir / "m.h5", h5::File::Mode::create);
    f.create_groups("/config");
    write_settings(f, "/config", msae_settings(c, t));
    CHECK(f.attr_string("/config", "support") == "hard");
    CHECK(f.attr_string("/config", "split") == "lists");
    f.set_attr("/config", "init", std::string("uniform"));
  }
  MsaeConfig back;
  MsaeTraining back_t;
  const h5::File f(dir / "m.h5", h5::File::Mode::read);
  const std::string msg =
      test::error_message([&] { read_settings(f, "/config", msae_settings(back, back_t)); });
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
  CHECK_NOTHROW(check_ranges(msae_settings(c, t)));  // the defaults lie inside
  t.lr = 0;
  CHECK_THAT(test::error_message([&] { check_ranges(msae_settings(c, t)); }),
             Catch::Contains("--lr must be positive (got 0)"));
  t.lr = 1e-3;
  c.d = {0.4, 1.5};  // every number of a list
  CHECK_THAT(test::error_message([&] { check_ranges(msae_settings(c, t)); }),
             Catch::Contains("--d must be in (0, 1] (got 0.4,1.5)"));
  BdlstmConfig bc;
  BdlstmTraining bt;
  CHECK_NOTHROW(check_ranges(bdlstm_settings(bc, bt)));
  bt.window = 1;
  CHECK_THROWS_AS(check_ranges(bdlstm_settings(bc, bt)), UsageError);
  ActganConfig ac;
  ActganTraining at;
  CHECK_NOTHROW(check_ranges(actgan_settings(ac, at)));
  at.batch = 1;
  CHECK_THAT(test::error_message([&] { check_ranges(actgan_settings(ac, at)); }),
             Catch::Contains("--batch must be at least 2 (got 1)"));
}
