// libFuzzer target: schema validation of our HDF5 file kinds (what h5check and every tool run
// on open). The input bytes do not become the HDF5 bytes (the HDF5 library itself is not ours
// to fuzz); they steer a generator of structurally valid HDF5 files of a kind: which datasets
// exist, their dtype, rank and dimensions (consistent with the schema, off by a little, zero,
// or huge and unallocated), their values (indices out of range, NaN, Inf, decreasing offsets)
// and the attributes. Validation must answer every such file with an InvalidInput or accept
// it, without crashing and without allocating what a huge declared shape asks for.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "core/error.h"
#include "fuzz_common.h"
#include "io/h5.h"
#include "io/schema.h"

namespace {

using df::h5::Dtype;
using nlohmann::json;

constexpr std::size_t kMaxWrittenElements = 4096;
const Dtype kDtypes[] = {Dtype::f32, Dtype::f64, Dtype::i32, Dtype::i64, Dtype::u8, Dtype::string};

class Generator {
 public:
  Generator(FuzzedDataProvider& in, df::h5::File& f) : in_(in), f_(f) {}

  void file(const std::string& kind) {
    const json& doc = df::io::schema(kind).doc;
    for (auto& [name, _] : doc["dimensions"].items()) dims_[name] = dimension();
    root_attributes(kind, doc);
    for (const json& o : doc["objects"]) {
      if (o.value("type", "") == "group")
        group(o);
      else if (o.value("required", false) ? !in_.ConsumeBool() || in_.ConsumeBool()
                                          : in_.ConsumeBool())
        dataset(o);
    }
  }

 private:
  // Mostly small sizes (so the data is written), sometimes zero or huge (declared only).
  std::size_t dimension() {
    switch (in_.ConsumeIntegralInRange(0, 9)) {
      case 0:
        return 0;
      case 1:
        return std::size_t(1) << in_.ConsumeIntegralInRange(16, 40);
      default:
        return in_.ConsumeIntegralInRange<std::size_t>(1, 6);
    }
  }

  void attribute(const std::string& object, const json& a) {
    const std::string name = a.at("name"), type = a.value("type", "string");
    if (in_.ConsumeIntegralInRange(0, 7) == 0) return;  // missing
    if (type == "string" || in_.ConsumeIntegralInRange(0, 7) == 0) {
      std::string v =
          a.contains("enum") && in_.ConsumeBool()
              ? a["enum"][in_.ConsumeIntegralInRange<std::size_t>(0, a["enum"].size() - 1)]
                    .get<std::string>()
              : in_.ConsumeRandomLengthString(16);
      f_.set_attr(object, name, v);
    } else if (type == "integer") {
      f_.set_attr(object, name, in_.ConsumeIntegral<std::int64_t>());
    } else if (type == "numbers") {
      std::vector<double> v(in_.ConsumeIntegralInRange(0, 4));
      for (double& x : v) x = number();
      f_.set_attr(object, name, std::span<const double>(v));
    } else {
      f_.set_attr(object, name, number());
    }
  }

  double number() {
    switch (in_.ConsumeIntegralInRange(0, 7)) {
      case 0:
        return std::numeric_limits<double>::quiet_NaN();
      case 1:
        return std::numeric_limits<double>::infinity();
      default:
        return in_.ConsumeFloatingPointInRange(-1e3, 1e3);
    }
  }

  void root_attributes(const std::string& kind, const json& doc) {
    f_.set_attr("/", "schema",
                in_.ConsumeIntegralInRange(0, 15) == 0 ? in_.ConsumeRandomLengthString(8) : kind);
    f_.set_attr("/", "schema_version",
                static_cast<std::int64_t>(in_.ConsumeIntegralInRange(-1, 2)));
    for (const char* name : {"tool", "tool_version", "history"})
      if (in_.ConsumeIntegralInRange(0, 15) != 0)
        f_.set_attr("/", name, in_.ConsumeRandomLengthString(8));
    for (const json& a : doc["attributes"]) attribute("/", a);
  }

  void group(const json& o) {
    if (!in_.ConsumeBool()) return;
    f_.create_groups(o.at("path"));
    if (o.contains("attributes"))
      for (const json& a : o["attributes"]) attribute(o.at("path"), a);
  }

  std::vector<std::size_t> shape(const json& spec) {
    std::vector<std::size_t> dims;
    for (const json& s : spec) {
      if (s.is_number_integer()) {
        dims.push_back(s.get<std::size_t>());
      } else {
        std::string name = s.get<std::string>();
        std::size_t plus = name.ends_with("+1") ? 1 : 0;
        if (plus) name.resize(name.size() - 2);
        dims.push_back(dims_.count(name) ? dims_[name] + plus : 2);
      }
    }
    switch (in_.ConsumeIntegralInRange(0, 11)) {  // now and then: off by one, another rank
      case 0:
        if (!dims.empty()) dims[in_.ConsumeIntegralInRange<std::size_t>(0, dims.size() - 1)] += 1;
        break;
      case 1:
        dims.push_back(in_.ConsumeIntegralInRange<std::size_t>(1, 3));
        break;
      case 2:
        if (!dims.empty()) dims.pop_back();
        break;
      case 3:
        if (!dims.empty())
          dims[in_.ConsumeIntegralInRange<std::size_t>(0, dims.size() - 1)] = dimension();
        break;
      default:
        break;
    }
    return dims;
  }

  void dataset(const json& o) {
    const std::string path = o.at("path");
    Dtype dtype = df::h5::dtype_from_name(o.at("dtype"));
    if (in_.ConsumeIntegralInRange(0, 9) == 0) dtype = in_.PickValueInArray(kDtypes);
    std::vector<std::size_t> dims = shape(o.at("shape"));
    long double count = 1;
    for (auto d : dims) count *= static_cast<long double>(d);
    if (count > kMaxWrittenElements) {
      declare_only(path, dtype, dims);
      return;
    }
    auto n = static_cast<std::size_t>(count);
    switch (dtype) {
      case Dtype::f32:
        write<float>(path, dims, n, [&] { return static_cast<float>(number()); });
        break;
      case Dtype::f64:
        write<double>(path, dims, n, [&] { return number(); });
        break;
      case Dtype::i32:
        write<std::int32_t>(path, dims, n, [&] { return integer<std::int32_t>(); });
        break;
      case Dtype::i64:
        write<std::int64_t>(path, dims, n, [&] { return integer<std::int64_t>(); });
        break;
      case Dtype::u8:
        write<std::uint8_t>(path, dims, n, [&] { return in_.ConsumeIntegral<std::uint8_t>(); });
        break;
      default: {
        std::vector<std::string> v(n);
        for (auto& s : v) s = in_.ConsumeRandomLengthString(8);
        if (dims.size() == 1) f_.write_strings(path, v);
        break;
      }
    }
  }

  // Small values (valid indices and offsets are small), sometimes anything.
  template <class T>
  T integer() {
    return in_.ConsumeIntegralInRange(0, 7) == 0 ? in_.ConsumeIntegral<T>()
                                                 : in_.ConsumeIntegralInRange<T>(-2, 8);
  }

  template <class T, class Fn>
  void write(const std::string& path, const std::vector<std::size_t>& dims, std::size_t n,
             Fn value) {
    std::vector<T> v(n);
    for (T& x : v) x = value();
    f_.write<T>(path, std::span<const T>(v), dims);
  }

  void declare_only(const std::string& path, Dtype dtype, const std::vector<std::size_t>& dims) {
    switch (dtype) {
      case Dtype::f32:
        f_.create<float>(path, dims);
        break;
      case Dtype::f64:
        f_.create<double>(path, dims);
        break;
      case Dtype::i32:
        f_.create<std::int32_t>(path, dims);
        break;
      case Dtype::u8:
        f_.create<std::uint8_t>(path, dims);
        break;
      default:
        f_.create<std::int64_t>(path, dims);
        break;
    }
  }

  FuzzedDataProvider& in_;
  df::h5::File& f_;
  std::map<std::string, std::size_t> dims_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  static const std::vector<std::string> kinds = df::io::schema_kinds();
  const std::string kind = kinds[in.ConsumeIntegralInRange<std::size_t>(0, kinds.size() - 1)];
  const std::string path = df::fuzz::scratch() + "/input.h5";
  try {
    df::h5::File f(path, df::h5::File::Mode::create);
    Generator(in, f).file(kind);
    f.close();
  } catch (const df::Error&) {
    return 0;  // the generator asked HDF5 for something it refuses: not a file to validate
  }
  for (bool tool_options : {true, false}) {  // a tool opening it, and h5check
    try {
      df::h5::File f(path, df::h5::File::Mode::read);
      df::io::validate(f, "",
                       tool_options ? df::io::tool_validation() : df::io::ValidationOptions{});
    } catch (const df::InvalidInput&) {
    } catch (const df::IOError&) {
    }
  }
  return 0;
}
