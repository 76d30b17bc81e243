#include "io/schema.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>

#include "core/error.h"
#include "core/log.h"

using nlohmann::json;

namespace df::io {
namespace {

std::map<std::string, Schema> load_all() {
  std::map<std::string, Schema> out;
  for (const auto& [stem, text] : embedded_schemas()) {
    Schema s;
    s.doc = json::parse(text);
    s.kind = s.doc.at("kind").get<std::string>();
    s.version = s.doc.at("version").get<int>();
    if (s.kind != stem) throw Error("schema file " + stem + ".json declares kind " + s.kind);
    out.emplace(s.kind, std::move(s));
  }
  return out;
}

const std::map<std::string, Schema>& all() {
  static const std::map<std::string, Schema> schemas = load_all();
  return schemas;
}

std::string shape_string(const std::vector<std::size_t>& d) {
  std::string s = "[";
  for (std::size_t i = 0; i < d.size(); ++i) s += (i ? "," : "") + std::to_string(d[i]);
  return s + "]";
}

std::string index_string(std::size_t flat, const std::vector<std::size_t>& dims) {
  std::vector<std::size_t> idx(dims.size());
  for (std::size_t i = dims.size(); i-- > 0;) {
    idx[i] = dims[i] ? flat % dims[i] : 0;
    flat = dims[i] ? flat / dims[i] : 0;
  }
  return shape_string(idx);
}

class Validator {
 public:
  Validator(const h5::File& f, const Schema& s, const ValidationOptions& opt)
      : f_(f), s_(s), opt_(opt) {}

  Dimensions run() {
    check_attributes("/", s_.doc.value("attributes", json::array()));
    for (const auto& group : s_.doc.value("require_any", json::array())) {
      bool any = false;
      std::string names;
      for (const auto& p : group) {
        any = any || f_.exists(p.get<std::string>());
        names += (names.empty() ? "" : ", ") + p.get<std::string>();
      }
      if (!any) fail("needs at least one of " + names, "/");
    }
    for (const auto& o : s_.doc.at("objects")) check_object(o);
    for (const auto& [name, size] : dims_) check_dimension_rules(name, size);
    return dims_;
  }

 private:
  [[noreturn]] void fail(const std::string& what, const std::string& object) const {
    throw InvalidInput(what, f_.where(object));
  }

  void check_object(const json& o) {
    const std::string path = o.at("path");
    bool present = f_.exists(path);
    bool required = o.value("required", false);
    if (o.contains("required_with") && f_.exists(o["required_with"].get<std::string>()))
      required = true;
    if (!present) {
      if (required)
        fail(fmt::format("missing {} (required in a '{}' file)",
                         o.value("type", "dataset") == "group" ? "group" : "dataset", s_.kind),
             path);
      return;
    }
    for (const auto& r : o.value("requires", json::array()))
      if (!f_.exists(r.get<std::string>()))
        fail("present without " + r.get<std::string>() + ", which it needs", path);
    if (o.value("type", "dataset") == "group") {
      if (!f_.is_group(path)) fail("should be a group", path);
    } else {
      check_dataset(o, path);
    }
    check_attributes(path, o.value("attributes", json::array()));
  }

  void check_attributes(const std::string& object, const json& attrs) {
    for (const auto& a : attrs) {
      const std::string name = a.at("name");
      if (!f_.has_attr(object, name)) {
        if (a.value("required", false)) fail("missing attribute '" + name + "'", object);
        continue;
      }
      const std::string type = a.value("type", "string");
      if (type == "string") {
        std::string v = f_.attr_string(object, name);
        if (a.contains("enum")) {
          auto e = a["enum"].get<std::vector<std::string>>();
          if (std::find(e.begin(), e.end(), v) == e.end())
            fail(fmt::format("attribute '{}' is '{}', expected one of: {}", name, v,
                             fmt::join(e, ", ")),
                 object);
        }
      } else if (type == "number") {
        double v = f_.attr_double(object, name);
        if (!std::isfinite(v)) fail("attribute '" + name + "' is not finite", object);
      } else if (type == "integer") {
        f_.attr_int(object, name);
      } else if (type == "numbers") {  // a non-empty array of finite numbers
        const auto v = f_.attr_doubles(object, name);
        if (v.empty() ||
            !std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }))
          fail("attribute '" + name + "' is not a non-empty array of finite numbers", object);
      }
    }
  }

  void check_dataset(const json& o, const std::string& path) {
    if (!f_.is_dataset(path)) fail("should be a dataset", path);
    h5::DatasetInfo info = f_.info(path);
    const std::string dtype = o.at("dtype");
    if (h5::dtype_from_name(dtype) != info.dtype)
      fail(fmt::format("has type {}, expected {}", h5::dtype_name(info.dtype), dtype), path);
    const json& shape = o.at("shape");
    if (shape.size() != info.dims.size())
      fail(fmt::format("has rank {} (shape {}), expected rank {} ({})", info.dims.size(),
                       shape_string(info.dims), shape.size(), shape.dump()),
           path);
    for (std::size_t i = 0; i < shape.size(); ++i) bind(shape[i], info.dims[i], path, i);
    // A declared shape without stored data reads as fill values: a crafted or foreign file, and
    // scanning a huge one would take hours (found by fuzzing).
    if (!info.fully_stored)
      fail(fmt::format("declares shape {} but does not store its data", shape_string(info.dims)),
           path);
    if (!opt_.check_values) return;
    std::size_t bytes = (info.dtype == h5::Dtype::f32 ? 4 : 8);
    for (auto d : info.dims) bytes *= d;
    if (o.value("finite", false) && bytes <= opt_.max_finite_scan_bytes) check_finite(path, info);
    if (o.contains("index_of"))
      check_indices(path, info, o["index_of"], o.value("allow_minus_one", false));
    if (o.contains("offsets_of")) check_offsets(path, o["offsets_of"]);
  }

  // Binds a named dimension ("V", "S+1") to an actual size, or checks it against the size it
  // already has from an earlier dataset.
  void bind(const json& spec, std::size_t actual, const std::string& path, std::size_t axis) {
    if (spec.is_number_integer()) {
      if (actual != spec.get<std::size_t>())
        fail(fmt::format("axis {} has size {}, expected {}", axis, actual, spec.get<std::size_t>()),
             path);
      return;
    }
    std::string s = spec.get<std::string>();
    std::size_t plus = 0;
    if (auto p = s.find('+'); p != std::string::npos) {
      plus = std::stoul(s.substr(p + 1));
      s = s.substr(0, p);
    }
    if (actual < plus)
      fail(fmt::format("axis {} has size {}, expected {}", axis, actual, spec.get<std::string>()),
           path);
    std::size_t value = actual - plus;
    auto it = dims_.find(s);
    if (it == dims_.end()) {
      dims_[s] = value;
      first_[s] = path;
    } else if (it->second != value) {
      std::string meaning =
          s_.doc["dimensions"].contains(s) ? s_.doc["dimensions"][s].value("description", s) : s;
      fail(fmt::format("axis {} implies {} = {} ({}), but {} has {} = {}", axis, s, value, meaning,
                       first_[s], s, it->second),
           path);
    }
  }

  void check_dimension_rules(const std::string& name, std::size_t size) {
    if (!s_.doc["dimensions"].contains(name)) return;
    const json& d = s_.doc["dimensions"][name];
    if (d.contains("min") && size < d["min"].get<std::size_t>())
      fail(fmt::format("{} = {} ({}) but at least {} needed", name, size,
                       d.value("description", name), d["min"].get<std::size_t>()),
           first_[name]);
    if (d.contains("values")) {
      auto v = d["values"].get<std::vector<std::size_t>>();
      if (std::find(v.begin(), v.end(), size) == v.end())
        fail(fmt::format("{} = {} ({}) but must be one of {}", name, size,
                         d.value("description", name), fmt::join(v, ", ")),
             first_[name]);
    }
  }

  // Reads the dataset in blocks of rows so that huge feature arrays need little memory.
  template <class T, class Fn>
  void scan(const std::string& path, const h5::DatasetInfo& info, Fn&& fn) {
    // Nothing to read when an axis is zero; a huge first axis over empty rows would otherwise
    // be walked block by block for hours (found by fuzzing: shape [2^40, 0]).
    if (info.dims.empty() || std::find(info.dims.begin(), info.dims.end(), 0) != info.dims.end())
      return;
    std::size_t row = 1;
    for (std::size_t i = 1; i < info.dims.size(); ++i) row *= info.dims[i];
    std::size_t rows_per_block =
        std::max<std::size_t>(1, (8u << 20) / std::max<std::size_t>(row * sizeof(T), 1));
    std::vector<T> buf;
    for (std::size_t first = 0; first < info.dims[0]; first += rows_per_block) {
      std::size_t count = std::min(rows_per_block, info.dims[0] - first);
      buf.resize(count * row);
      f_.read_rows<T>(path, first, count, buf.data());
      for (std::size_t i = 0; i < buf.size(); ++i) fn(first * row + i, buf[i]);
    }
  }

  void check_finite(const std::string& path, const h5::DatasetInfo& info) {
    auto test = [&](std::size_t flat, double v) {
      if (!std::isfinite(v))
        fail(fmt::format("{} at index {}", std::isnan(v) ? "NaN" : "Inf",
                         index_string(flat, info.dims)),
             path);
    };
    if (info.dtype == h5::Dtype::f32)
      scan<float>(path, info, [&](std::size_t i, float v) { test(i, v); });
    else
      scan<double>(path, info, [&](std::size_t i, double v) { test(i, v); });
  }

  void check_indices(const std::string& path, const h5::DatasetInfo& info, const std::string& dim,
                     bool allow_minus_one) {
    auto it = dims_.find(dim);
    if (it == dims_.end()) return;  // bound by an optional dataset that is absent
    auto limit = static_cast<std::int64_t>(it->second);
    scan<std::int64_t>(path, info, [&](std::size_t flat, std::int64_t v) {
      if ((v < 0 && !(allow_minus_one && v == -1)) || v >= limit)
        fail(fmt::format("value {} at index {} is not a valid index ({} = {})", v,
                         index_string(flat, info.dims), dim, limit),
             path);
    });
  }

  void check_offsets(const std::string& path, const std::string& dim) {
    auto offsets = f_.read<std::int64_t>(path).data;
    auto it = dims_.find(dim);
    if (offsets.empty() || offsets.front() != 0) fail("offsets must start at 0", path);
    for (std::size_t i = 1; i < offsets.size(); ++i)
      if (offsets[i] < offsets[i - 1])
        fail(fmt::format("offsets decrease at index {} ({} after {})", i, offsets[i],
                         offsets[i - 1]),
             path);
    if (it != dims_.end() && offsets.back() != static_cast<std::int64_t>(it->second))
      fail(fmt::format("offsets end at {} but there are {} = {} frames", offsets.back(), dim,
                       it->second),
           path);
  }

  const h5::File& f_;
  const Schema& s_;
  ValidationOptions opt_;
  Dimensions dims_;
  std::map<std::string, std::string> first_;  // dimension -> dataset that bound it
};

}  // namespace

ValidationOptions tool_validation() {
  ValidationOptions o;
  o.max_finite_scan_bytes = 64u << 20;
  return o;
}

template <class T>
void check_finite_rows(const T* data, std::size_t first, std::size_t count, std::size_t row_size,
                       const std::string& where) {
  for (std::size_t k = 0; k < count * row_size; ++k)
    if (!std::isfinite(data[k]))
      throw InvalidInput(
          fmt::format("{} in row {}, element {}", std::isnan(data[k]) ? "NaN" : "Inf",
                      first + k / row_size, k % row_size),
          where);
}
template void check_finite_rows<float>(const float*, std::size_t, std::size_t, std::size_t,
                                       const std::string&);
template void check_finite_rows<double>(const double*, std::size_t, std::size_t, std::size_t,
                                        const std::string&);

const Schema& schema(const std::string& kind) {
  auto it = all().find(kind);
  if (it == all().end())
    throw InvalidInput(
        fmt::format("unknown file kind '{}' (known: {})", kind, fmt::join(schema_kinds(), ", ")));
  return it->second;
}

std::vector<std::string> schema_kinds() {
  std::vector<std::string> k;
  for (const auto& [name, _] : all()) k.push_back(name);
  return k;
}

std::string declared_kind(const h5::File& f) {
  if (!f.has_attr("/", "schema"))
    throw InvalidInput("not a deformflow file (no 'schema' attribute at the root)", f.name());
  return f.attr_string("/", "schema");
}

Dimensions validate(const h5::File& f, const std::string& expected_kind,
                    const ValidationOptions& opt) {
  std::string kind = declared_kind(f);
  if (!expected_kind.empty() && kind != expected_kind)
    throw InvalidInput(fmt::format("is a '{}' file, expected a '{}' file", kind, expected_kind),
                       f.name());
  const Schema& s = schema(kind);
  for (const auto& a : kCommonRootAttributes)
    if (!f.has_attr("/", a)) throw InvalidInput("missing root attribute '" + a + "'", f.name());
  auto version = f.attr_int("/", "schema_version");
  if (version > s.version)
    throw InvalidInput(fmt::format("'{}' schema version {} is newer than this build knows ({}); "
                                   "update deformflow",
                                   kind, version, s.version),
                       f.name());
  return Validator(f, s, opt).run();
}

namespace {
constexpr std::uintmax_t kAnnouncedBytes = 64u << 20;  // inputs that take seconds to check
}  // namespace

h5::File open_input(const std::string& path, const std::string& kind, Dimensions* dims,
                    const ValidationOptions& opt) {
  h5::File f(path, h5::File::Mode::read);
  // Validation reads every dataset (NaN/Inf checks): say so before a large file's long silence.
  std::error_code ec;
  if (const auto bytes = std::filesystem::file_size(path, ec); !ec && bytes >= kAnnouncedBytes)
    log::info("reading {} ({:.0f} MB)", path, static_cast<double>(bytes) / 1e6);
  Dimensions d = validate(f, kind, opt);
  if (dims) *dims = std::move(d);
  return f;
}

void require_same_dimension(const std::string& name, const Dimensions& a, const std::string& file_a,
                            const Dimensions& b, const std::string& file_b) {
  auto ia = a.find(name), ib = b.find(name);
  if (ia == a.end() || ib == b.end()) return;
  if (ia->second != ib->second)
    throw InvalidInput(fmt::format("{} has {} = {} but {} has {} = {}", file_a, name, ia->second,
                                   file_b, name, ib->second),
                       file_b);
}

}  // namespace df::io
