// Test driver (not installed): compares one output of a golden-file case with its expected
// file. HDF5 files dataset by dataset and attribute by attribute (provenance attributes
// `history` and `tool_version` skipped), PNG pictures pixel by pixel, text files (tables,
// JSON, OBJ/OFF/PLY meshes) token by token with numbers compared numerically; anything else
// byte for byte. Numbers match when |got - want| <= abs + rel * |want|; the tolerance of an
// item is the first line of the --tolerances file whose glob matches "FILE" or
// "FILE:/dataset" (lines "GLOB ABS REL", '#' comments), else the defaults. Prints the first
// differences readably and exits 1 when any exceed their tolerance.
#include <cairo.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fnmatch.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/tool.h"
#include "io/h5.h"

namespace {

struct Tolerance {
  double abs = 1e-10;
  double rel = 1e-8;
};

struct Rule {
  std::string glob;
  Tolerance tol;
};

std::vector<Rule> read_rules(const std::string& path) {
  std::vector<Rule> rules;
  if (path.empty()) return rules;
  std::ifstream in(path);
  if (!in) throw df::InvalidInput("cannot read the tolerances", path);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    Rule r;
    if (!(fields >> r.glob)) continue;
    if (!(fields >> r.tol.abs >> r.tol.rel))
      throw df::InvalidInput("expected 'GLOB ABS REL'", path + ":" + std::to_string(n));
    rules.push_back(r);
  }
  return rules;
}

/// Collects differences; prints the first few, counts all.
class Report {
 public:
  Report(std::string file, std::vector<Rule> rules)
      : file_(std::move(file)), rules_(std::move(rules)) {}

  Tolerance tolerance(const std::string& item) const {
    std::string key = item.empty() ? file_ : file_ + ":" + item;
    for (const Rule& r : rules_)
      if (fnmatch(r.glob.c_str(), key.c_str(), 0) == 0) return r.tol;
    return {};
  }
  bool close(double got, double want, const Tolerance& t) const {
    if (std::isnan(got) || std::isnan(want)) return std::isnan(got) && std::isnan(want);
    return std::abs(got - want) <= t.abs + t.rel * std::abs(want);
  }
  void differ(const std::string& where, const std::string& what) {
    if (++count_ <= kShown) std::printf("  %s%s: %s\n", file_.c_str(), where.c_str(), what.c_str());
  }
  /// Compares numbers element by element; `where(i)` names element i.
  template <class Where>
  void numbers(const std::vector<double>& got, const std::vector<double>& want, const Tolerance& t,
               Where where) {
    double worst = 0;
    std::size_t bad = 0;
    for (std::size_t i = 0; i < want.size(); ++i) {
      if (close(got[i], want[i], t)) continue;
      if (bad++ < 3)
        differ(where(i), fmt::format("expected {:.10g}, got {:.10g} (tolerance abs {:g} rel {:g})",
                                     want[i], got[i], t.abs, t.rel));
      worst = std::max(worst, std::abs(got[i] - want[i]));
    }
    if (bad > 3)
      differ(where(std::size_t(-1)),
             fmt::format("{} of {} values differ, largest by {:.3g}", bad, want.size(), worst));
  }
  int count() const { return count_; }

 private:
  static constexpr int kShown = 12;
  std::string file_;
  std::vector<Rule> rules_;
  int count_ = 0;
};

// --- HDF5

bool is_provenance(const std::string& object, const std::string& name) {
  return object == "/" && (name == "history" || name == "tool_version");
}

std::string index_name(const std::vector<std::size_t>& dims, std::size_t flat) {
  if (flat == std::size_t(-1)) return "";
  std::vector<std::size_t> idx(dims.size());
  for (std::size_t d = dims.size(); d-- > 0;) {
    idx[d] = flat % dims[d];
    flat /= dims[d];
  }
  return fmt::format("[{}]", fmt::join(idx, ","));
}

void compare_attributes(const df::h5::File& got, const df::h5::File& want,
                        const std::string& object, Report& report) {
  for (const std::string& name : want.attr_names(object)) {
    if (is_provenance(object, name)) continue;
    std::string where = object + "@" + name;
    if (!got.has_attr(object, name)) {
      report.differ(where, "attribute missing");
      continue;
    }
    try {
      auto w = want.attr_doubles(object, name);
      auto g = got.attr_doubles(object, name);
      if (g.size() != w.size())
        report.differ(where, fmt::format("{} values, expected {}", g.size(), w.size()));
      else
        report.numbers(g, w, report.tolerance(where), [&](std::size_t i) {
          return i == std::size_t(-1) || w.size() == 1 ? where : fmt::format("{}[{}]", where, i);
        });
    } catch (const df::InvalidInput&) {  // not numeric: a string
      auto w = want.attr_string(object, name), g = got.attr_string(object, name);
      if (g != w) report.differ(where, fmt::format("'{}', expected '{}'", g, w));
    }
  }
  for (const std::string& name : got.attr_names(object))
    if (!is_provenance(object, name) && !want.has_attr(object, name))
      report.differ(object + "@" + name, "unexpected attribute");
}

void compare_dataset(const df::h5::File& got, const df::h5::File& want, const std::string& path,
                     Report& report) {
  auto wi = want.info(path), gi = got.info(path);
  if (wi.dtype != gi.dtype || wi.dims != gi.dims) {
    report.differ(path, fmt::format("{} [{}], expected {} [{}]", df::h5::dtype_name(gi.dtype),
                                    fmt::join(gi.dims, ","), df::h5::dtype_name(wi.dtype),
                                    fmt::join(wi.dims, ",")));
    return;
  }
  if (wi.dtype == df::h5::Dtype::string) {
    auto w = want.read_strings(path), g = got.read_strings(path);
    for (std::size_t i = 0; i < w.size(); ++i)
      if (g[i] != w[i])
        report.differ(fmt::format("{}[{}]", path, i),
                      fmt::format("'{}', expected '{}'", g[i], w[i]));
    return;
  }
  auto w = want.read<double>(path), g = got.read<double>(path);
  report.numbers(g.data, w.data, report.tolerance(path),
                 [&](std::size_t i) { return path + index_name(wi.dims, i); });
}

void compare_h5(const std::string& got_path, const std::string& want_path, Report& report) {
  df::h5::File want(want_path, df::h5::File::Mode::read), got(got_path, df::h5::File::Mode::read);
  compare_attributes(got, want, "/", report);
  for (const std::string& object : want.descendants()) {
    if (!got.exists(object)) {
      report.differ(object, "missing");
      continue;
    }
    if (want.is_dataset(object)) compare_dataset(got, want, object, report);
    compare_attributes(got, want, object, report);
  }
  for (const std::string& object : got.descendants())
    if (!want.exists(object)) report.differ(object, "unexpected object");
}

// --- PNG

void compare_png(const std::string& got_path, const std::string& want_path, Report& report) {
  auto load = [](const std::string& p) {
    cairo_surface_t* s = cairo_image_surface_create_from_png(p.c_str());
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
      cairo_surface_destroy(s);
      throw df::InvalidInput("not a readable PNG", p);
    }
    return s;
  };
  cairo_surface_t* w = load(want_path);
  cairo_surface_t* g = load(got_path);
  int width = cairo_image_surface_get_width(w), height = cairo_image_surface_get_height(w);
  if (cairo_image_surface_get_width(g) != width || cairo_image_surface_get_height(g) != height) {
    report.differ("", fmt::format("{}x{} pixels, expected {}x{}", cairo_image_surface_get_width(g),
                                  cairo_image_surface_get_height(g), width, height));
  } else {
    // channel values 0..255; a tolerance of abs 2 allows rounding differences of anti-aliasing
    std::vector<double> wv, gv;
    for (auto [s, v] : {std::pair{w, &wv}, std::pair{g, &gv}}) {
      cairo_surface_flush(s);
      const unsigned char* data = cairo_image_surface_get_data(s);
      int stride = cairo_image_surface_get_stride(s);
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < 4 * width; ++x) v->push_back(data[y * stride + x]);
    }
    report.numbers(gv, wv, report.tolerance(""), [&](std::size_t i) {
      return i == std::size_t(-1) ? std::string()
                                  : fmt::format(" pixel ({},{})", (i / 4) % width, i / 4 / width);
    });
  }
  cairo_surface_destroy(w);
  cairo_surface_destroy(g);
}

// --- text and bytes

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw df::InvalidInput("cannot read", path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool parse_number(const std::string& token, double& value) {
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  return !token.empty() && end == token.c_str() + token.size();
}

std::vector<std::string> tokens(const std::string& line) {
  // numbers are separated from punctuation (JSON's "1.5," or "[2,") before splitting
  std::string spaced;
  for (char c : line) {
    if (std::string_view(",[]{}:|()=;").find(c) != std::string_view::npos) {
      spaced += ' ';
      spaced += c;
      spaced += ' ';
    } else {
      spaced += c;
    }
  }
  std::istringstream in(spaced);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

void compare_text(const std::string& got, const std::string& want, Report& report) {
  std::istringstream gs(got), ws(want);
  std::string gl, wl;
  Tolerance tol = report.tolerance("");
  for (int n = 1;; ++n) {
    bool has_g = static_cast<bool>(std::getline(gs, gl)),
         has_w = static_cast<bool>(std::getline(ws, wl));
    if (!has_g && !has_w) return;
    if (has_g != has_w) {
      report.differ(fmt::format(":{}", n),
                    has_w ? "output ends early, expected: " + wl : "extra line: " + gl);
      return;
    }
    auto gt = tokens(gl), wt = tokens(wl);
    bool same = gt.size() == wt.size();
    for (std::size_t i = 0; same && i < wt.size(); ++i) {
      double g = 0, w = 0;
      same = gt[i] == wt[i] ||
             (parse_number(gt[i], g) && parse_number(wt[i], w) && report.close(g, w, tol));
    }
    if (!same)
      report.differ(fmt::format(":{}", n),
                    fmt::format("\n    expected: {}\n    got:      {}", wl, gl));
  }
}

void compare_file(const std::string& got_path, const std::string& want_path, Report& report) {
  auto ends_with = [&](const char* ext) { return want_path.ends_with(ext); };
  if (ends_with(".h5")) return compare_h5(got_path, want_path, report);
  if (ends_with(".png")) return compare_png(got_path, want_path, report);
  std::string got = slurp(got_path), want = slurp(want_path);
  if (want.find('\0') == std::string::npos && got.find('\0') == std::string::npos)
    return compare_text(got, want, report);
  if (got != want)
    report.differ(
        "", fmt::format("binary files differ ({} bytes, expected {})", got.size(), want.size()));
}

}  // namespace

int main(int argc, char** argv) {
  df::Tool tool("golden_compare", "Compare an output with its expected golden file (test driver).");
  std::string got, want, tolerances, name;
  tool.app().add_option("--tolerances", tolerances, "file of 'GLOB ABS REL' lines");
  tool.app().add_option("--name", name, "the output's name in the case (matched by the globs)");
  tool.app().add_option("GOT", got)->required();
  tool.app().add_option("EXPECTED", want)->required();
  int status = 0;
  int rc = tool.run(argc, argv, [&] {
    Report report(name.empty() ? got : name, read_rules(tolerances));
    compare_file(got, want, report);
    if (report.count() > 0) {
      std::printf("  %s: %d difference%s beyond tolerance\n", (name.empty() ? got : name).c_str(),
                  report.count(), report.count() == 1 ? "" : "s");
      status = 1;
    }
  });
  return rc != 0 ? rc : status;
}
