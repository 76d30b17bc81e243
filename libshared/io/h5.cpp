#include "io/h5.h"

#include <tbb/parallel_for.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <numeric>

#include "core/error.h"
#include "io/zstd_filter.h"

namespace fs = std::filesystem;

namespace df::h5 {
namespace {

// The innermost message of HDF5's error stack (the most specific one), then clears it.
std::string hdf5_detail() {
  std::string msg;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* e, void* data) -> herr_t {
        if (n == 0 && e && e->desc) *static_cast<std::string*>(data) = e->desc;
        return 0;
      },
      &msg);
  H5Eclear2(H5E_DEFAULT);
  return msg;
}

[[noreturn]] void fail(const std::string& what, const std::string& where) {
  std::string detail = hdf5_detail();
  throw IOError(detail.empty() ? what : what + ": " + detail, where);
}

Handle checked(hid_t id, Handle::Closer closer, const std::string& what, const std::string& where) {
  if (id < 0) fail(what, where);
  return Handle(id, closer);
}

void check(herr_t status, const std::string& what, const std::string& where) {
  if (status < 0) fail(what, where);
}

std::string parent_of(const std::string& path) {
  auto pos = path.find_last_of('/');
  if (pos == std::string::npos || pos == 0) return "/";
  return path.substr(0, pos);
}

Dtype dtype_of(hid_t type) {
  switch (H5Tget_class(type)) {
    case H5T_FLOAT:
      return H5Tget_size(type) == 4   ? Dtype::f32
             : H5Tget_size(type) == 8 ? Dtype::f64
                                      : Dtype::other;
    case H5T_INTEGER: {
      bool sign = H5Tget_sign(type) == H5T_SGN_2;
      switch (H5Tget_size(type)) {
        case 1:
          return sign ? Dtype::i8 : Dtype::u8;
        case 4:
          return sign ? Dtype::i32 : Dtype::u32;
        case 8:
          return sign ? Dtype::i64 : Dtype::u64;
        default:
          return Dtype::other;
      }
    }
    case H5T_STRING:
      return Dtype::string;
    default:
      return Dtype::other;
  }
}

Handle utf8_string_type() {
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  return Handle(t, H5Tclose);
}

std::vector<std::size_t> space_dims(hid_t space) {
  int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> d(static_cast<std::size_t>(std::max(rank, 0)));
  if (rank > 0) H5Sget_simple_extent_dims(space, d.data(), nullptr);
  return {d.begin(), d.end()};
}

std::size_t product(const std::vector<std::size_t>& d, std::size_t from = 0) {
  std::size_t p = 1;
  for (std::size_t i = from; i < d.size(); ++i) p *= d[i];
  return p;
}

// Reads strings (variable- or fixed-length) of an attribute or dataset with the given type.
template <class ReadFn>
std::vector<std::string> read_string_values(hid_t file_type, std::size_t n, ReadFn read,
                                            const std::string& where) {
  std::vector<std::string> out(n);
  if (H5Tis_variable_str(file_type) > 0) {
    Handle mem = utf8_string_type();
    std::vector<char*> ptrs(n, nullptr);
    if (read(mem.get(), ptrs.data()) < 0) fail("cannot read strings", where);
    for (std::size_t i = 0; i < n; ++i) {
      if (ptrs[i]) out[i] = ptrs[i];
      H5free_memory(ptrs[i]);
    }
  } else {
    std::size_t len = H5Tget_size(file_type);
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem.get(), len);
    std::vector<char> buf(len * n + 1, 0);
    if (read(mem.get(), buf.data()) < 0) fail("cannot read strings", where);
    for (std::size_t i = 0; i < n; ++i) {
      const char* s = buf.data() + i * len;
      out[i] = std::string(s, strnlen(s, len));
    }
  }
  return out;
}

}  // namespace

const char* dtype_name(Dtype t) {
  switch (t) {
    case Dtype::f32:
      return "float32";
    case Dtype::f64:
      return "float64";
    case Dtype::i8:
      return "int8";
    case Dtype::u8:
      return "uint8";
    case Dtype::i32:
      return "int32";
    case Dtype::u32:
      return "uint32";
    case Dtype::i64:
      return "int64";
    case Dtype::u64:
      return "uint64";
    case Dtype::string:
      return "string";
    default:
      return "other";
  }
}

Dtype dtype_from_name(const std::string& name) {
  for (Dtype t : {Dtype::f32, Dtype::f64, Dtype::i8, Dtype::u8, Dtype::i32, Dtype::u32, Dtype::i64,
                  Dtype::u64, Dtype::string})
    if (name == dtype_name(t)) return t;
  return Dtype::other;
}

template <>
hid_t native_type<float>() {
  return H5T_NATIVE_FLOAT;
}
template <>
hid_t native_type<double>() {
  return H5T_NATIVE_DOUBLE;
}
template <>
hid_t native_type<std::int8_t>() {
  return H5T_NATIVE_INT8;
}
template <>
hid_t native_type<std::uint8_t>() {
  return H5T_NATIVE_UINT8;
}
template <>
hid_t native_type<std::int32_t>() {
  return H5T_NATIVE_INT32;
}
template <>
hid_t native_type<std::uint32_t>() {
  return H5T_NATIVE_UINT32;
}
template <>
hid_t native_type<std::int64_t>() {
  return H5T_NATIVE_INT64;
}
template <>
hid_t native_type<std::uint64_t>() {
  return H5T_NATIVE_UINT64;
}

void initialize() {
  static std::once_flag once;
  std::call_once(once, [] {
    H5open();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    register_zstd_filter();
  });
}

File::File(const fs::path& path, Mode mode, std::string display_name)
    : name_(display_name.empty() ? path.string() : std::move(display_name)) {
  initialize();
  const std::string p = path.string();
  if (mode == Mode::create) {
    Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
    H5Pset_obj_track_times(fcpl.get(), false);
    file_ = checked(H5Fcreate(p.c_str(), H5F_ACC_TRUNC, fcpl.get(), H5P_DEFAULT), H5Fclose,
                    "cannot create the HDF5 file", name_);
    return;
  }
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IOError("no such file", name_);
  if (fs::is_directory(path, ec)) throw InvalidInput("is a directory, not an HDF5 file", name_);
  htri_t is = H5Fis_hdf5(p.c_str());
  H5Eclear2(H5E_DEFAULT);
  if (is <= 0) throw InvalidInput("not an HDF5 file", name_);
  unsigned flags = mode == Mode::read ? H5F_ACC_RDONLY : H5F_ACC_RDWR;
  file_ =
      checked(H5Fopen(p.c_str(), flags, H5P_DEFAULT), H5Fclose, "cannot open the HDF5 file", name_);
}

void File::close() {
  if (!file_) return;
  check(H5Fflush(file_.get(), H5F_SCOPE_LOCAL), "cannot flush the file", name_);
  hid_t id = file_.release();
  check(H5Fclose(id), "cannot close the file", name_);
}

std::string File::where(const std::string& object) const {
  return object.empty() || object == "/" ? name_ : name_ + ":" + object;
}

bool File::exists(const std::string& path) const {
  if (path == "/" || path.empty()) return true;
  std::size_t pos = 0;
  while (true) {
    pos = path.find('/', pos + 1);
    std::string prefix = path.substr(0, pos);
    htri_t e = H5Lexists(file_.get(), prefix.c_str(), H5P_DEFAULT);
    if (e <= 0) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
    if (pos == std::string::npos) break;
  }
  htri_t ok = H5Oexists_by_name(file_.get(), path.c_str(), H5P_DEFAULT);
  H5Eclear2(H5E_DEFAULT);
  return ok > 0;
}

Handle File::open_object(const std::string& path) const {
  if (!exists(path)) throw InvalidInput("missing object", where(path));
  return checked(H5Oopen(file_.get(), path.c_str(), H5P_DEFAULT), H5Oclose, "cannot open object",
                 where(path));
}

Handle File::open_dataset(const std::string& path) const {
  if (!exists(path)) throw InvalidInput("missing dataset", where(path));
  if (!is_dataset(path)) throw InvalidInput("is not a dataset", where(path));
  return checked(H5Dopen2(file_.get(), path.c_str(), H5P_DEFAULT), H5Dclose, "cannot open dataset",
                 where(path));
}

bool File::is_group(const std::string& path) const {
  if (!exists(path)) return false;
  Handle o = open_object(path);
  return H5Iget_type(o.get()) == H5I_GROUP;
}

bool File::is_dataset(const std::string& path) const {
  if (!exists(path)) return false;
  Handle o(H5Oopen(file_.get(), path.c_str(), H5P_DEFAULT), H5Oclose);
  if (!o) fail("cannot open object", where(path));
  return H5Iget_type(o.get()) == H5I_DATASET;
}

std::vector<std::string> File::descendants(const std::string& group) const {
  std::vector<std::string> out;
  for (const std::string& name : children(group)) {
    out.push_back((group == "/" ? "" : group) + "/" + name);
    if (is_group(out.back())) {
      auto below = descendants(out.back());
      out.insert(out.end(), below.begin(), below.end());
    }
  }
  return out;
}

std::vector<std::string> File::children(const std::string& group) const {
  Handle g = checked(H5Gopen2(file_.get(), group.c_str(), H5P_DEFAULT), H5Gclose,
                     "cannot open group", where(group));
  H5G_info_t gi;
  check(H5Gget_info(g.get(), &gi), "cannot list group", where(group));
  std::vector<std::string> names;
  for (hsize_t i = 0; i < gi.nlinks; ++i) {
    ssize_t n =
        H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (n < 0) fail("cannot list group", where(group));
    std::string s(static_cast<std::size_t>(n), '\0');
    H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, s.data(),
                       static_cast<std::size_t>(n) + 1, H5P_DEFAULT);
    names.push_back(s);
  }
  return names;
}

void File::create_groups(const std::string& path) {
  if (path.empty() || path == "/") return;
  std::size_t pos = 0;
  Handle gcpl(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
  H5Pset_obj_track_times(gcpl.get(), false);
  while (pos != std::string::npos) {
    pos = path.find('/', pos + 1);
    std::string prefix = path.substr(0, pos);
    if (exists(prefix)) {
      if (!is_group(prefix)) throw InvalidInput("is not a group", where(prefix));
      continue;
    }
    checked(H5Gcreate2(file_.get(), prefix.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose,
            "cannot create group", where(prefix));
  }
}

// Whether every element of a dataset has storage: all chunks written (H5Dget_space_status
// cannot tell: HDF5 1.10 compares compressed bytes with the full size), or contiguous storage.
static bool stores_all_data(hid_t ds, hid_t dcpl, const std::vector<std::size_t>& dims) {
  if (std::find(dims.begin(), dims.end(), 0) != dims.end()) return true;
  switch (H5Pget_layout(dcpl)) {
    case H5D_CHUNKED: {
      std::vector<hsize_t> chunk(dims.size());
      if (H5Pget_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data()) < 0) return false;
      long double expected = 1;  // the count of chunks may exceed 64 bits for absurd shapes
      for (std::size_t i = 0; i < dims.size(); ++i)
        expected *= static_cast<long double>((dims[i] + chunk[i] - 1) / chunk[i]);
      hsize_t written = 0;
      Handle space(H5Dget_space(ds), H5Sclose);  // HDF5 1.10 refuses H5S_ALL here
      if (H5Dget_num_chunks(ds, space.get(), &written) < 0) return false;
      return static_cast<long double>(written) == expected;
    }
    case H5D_CONTIGUOUS:
      return H5Dget_storage_size(ds) > 0;
    default:
      return true;  // compact: stored in the header
  }
}

DatasetInfo File::info(const std::string& path) const {
  Handle ds = open_dataset(path);
  Handle type(H5Dget_type(ds.get()), H5Tclose);
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  Handle dcpl(H5Dget_create_plist(ds.get()), H5Pclose);
  DatasetInfo info;
  info.dtype = dtype_of(type.get());
  info.dims = space_dims(space.get());
  info.fully_stored = stores_all_data(ds.get(), dcpl.get(), info.dims);
  int nf = H5Pget_nfilters(dcpl.get());
  for (int i = 0; i < nf; ++i) {
    unsigned flags = 0;
    std::size_t nelem = 0;
    unsigned filter_config = 0;
    H5Z_filter_t id = H5Pget_filter2(dcpl.get(), static_cast<unsigned>(i), &flags, &nelem, nullptr,
                                     0, nullptr, &filter_config);
    info.filters.push_back(static_cast<int>(id));
  }
  return info;
}

// --- attributes

bool File::has_attr(const std::string& object, const std::string& name) const {
  if (!exists(object)) return false;
  htri_t e = H5Aexists_by_name(file_.get(), object.c_str(), name.c_str(), H5P_DEFAULT);
  H5Eclear2(H5E_DEFAULT);
  return e > 0;
}

std::vector<std::string> File::attr_names(const std::string& object) const {
  Handle o = open_object(object);
  std::vector<std::string> names;
  int n = H5Aget_num_attrs(o.get());
  for (int i = 0; i < n; ++i) {
    Handle a(H5Aopen_by_idx(o.get(), ".", H5_INDEX_NAME, H5_ITER_INC, static_cast<hsize_t>(i),
                            H5P_DEFAULT, H5P_DEFAULT),
             H5Aclose);
    if (!a) fail("cannot list attributes", where(object));
    ssize_t len = H5Aget_name(a.get(), 0, nullptr);
    std::string s(static_cast<std::size_t>(len), '\0');
    H5Aget_name(a.get(), static_cast<std::size_t>(len) + 1, s.data());
    names.push_back(s);
  }
  return names;
}

void File::write_attr_raw(const std::string& object, const std::string& name, hid_t type,
                          hid_t space, const void* data) {
  if (!exists(object)) create_groups(object);
  if (has_attr(object, name))
    check(H5Adelete_by_name(file_.get(), object.c_str(), name.c_str(), H5P_DEFAULT),
          "cannot replace attribute " + name, where(object));
  Handle a = checked(H5Acreate_by_name(file_.get(), object.c_str(), name.c_str(), type, space,
                                       H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                     H5Aclose, "cannot create attribute " + name, where(object));
  check(H5Awrite(a.get(), type, data), "cannot write attribute " + name, where(object));
}

void File::set_attr(const std::string& object, const std::string& name, const std::string& value) {
  Handle type = utf8_string_type();
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  const char* p = value.c_str();
  write_attr_raw(object, name, type.get(), space.get(), &p);
}

void File::set_attr(const std::string& object, const std::string& name, double value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  write_attr_raw(object, name, H5T_NATIVE_DOUBLE, space.get(), &value);
}

void File::set_attr(const std::string& object, const std::string& name, std::int64_t value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  write_attr_raw(object, name, H5T_NATIVE_INT64, space.get(), &value);
}

void File::set_attr(const std::string& object, const std::string& name, std::span<const double> v) {
  hsize_t n = v.size();
  Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  write_attr_raw(object, name, H5T_NATIVE_DOUBLE, space.get(), v.data());
}

namespace {
struct OpenAttr {
  Handle attr, type, space;
  std::size_t count;
};
}  // namespace

static OpenAttr open_attr(hid_t file, const std::string& object, const std::string& name,
                          const std::string& where) {
  OpenAttr a;
  htri_t e = H5Aexists_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT);
  H5Eclear2(H5E_DEFAULT);
  if (e <= 0) throw InvalidInput("missing attribute '" + name + "'", where);
  a.attr = checked(H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
                   H5Aclose, "cannot open attribute " + name, where);
  a.type = Handle(H5Aget_type(a.attr.get()), H5Tclose);
  a.space = Handle(H5Aget_space(a.attr.get()), H5Sclose);
  a.count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(a.space.get()));
  return a;
}

std::string File::attr_string(const std::string& object, const std::string& name) const {
  OpenAttr a = open_attr(file_.get(), object, name, where(object));
  if (H5Tget_class(a.type.get()) != H5T_STRING)
    throw InvalidInput("attribute '" + name + "' is not a string", where(object));
  auto v = read_string_values(
      a.type.get(), a.count, [&](hid_t mem, void* buf) { return H5Aread(a.attr.get(), mem, buf); },
      where(object));
  return v.empty() ? std::string() : v.front();
}

std::vector<double> File::attr_doubles(const std::string& object, const std::string& name) const {
  OpenAttr a = open_attr(file_.get(), object, name, where(object));
  auto cls = H5Tget_class(a.type.get());
  if (cls != H5T_FLOAT && cls != H5T_INTEGER)
    throw InvalidInput("attribute '" + name + "' is not numeric", where(object));
  std::vector<double> v(a.count);
  check(H5Aread(a.attr.get(), H5T_NATIVE_DOUBLE, v.data()), "cannot read attribute " + name,
        where(object));
  return v;
}

double File::attr_double(const std::string& object, const std::string& name) const {
  auto v = attr_doubles(object, name);
  if (v.size() != 1)
    throw InvalidInput("attribute '" + name + "' is not a single number", where(object));
  return v[0];
}

std::int64_t File::attr_int(const std::string& object, const std::string& name) const {
  OpenAttr a = open_attr(file_.get(), object, name, where(object));
  if (H5Tget_class(a.type.get()) != H5T_INTEGER || a.count != 1)
    throw InvalidInput("attribute '" + name + "' is not a single integer", where(object));
  std::int64_t v = 0;
  check(H5Aread(a.attr.get(), H5T_NATIVE_INT64, &v), "cannot read attribute " + name,
        where(object));
  return v;
}

// --- datasets

Handle File::make_dataset(const std::string& path, hid_t type, const std::vector<std::size_t>& dims,
                          std::size_t elem_size, const StorageOptions& opt) {
  create_groups(parent_of(path));
  if (exists(path))
    check(H5Ldelete(file_.get(), path.c_str(), H5P_DEFAULT), "cannot replace dataset", where(path));
  std::vector<hsize_t> hd(dims.begin(), dims.end());
  Handle space(H5Screate_simple(static_cast<int>(hd.size()), hd.data(), nullptr), H5Sclose);
  if (!space) fail("cannot create dataspace", where(path));
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_obj_track_times(dcpl.get(), false);
  std::size_t total = product(dims) * elem_size;
  if (opt.compress && !dims.empty() && total > 4096) {
    // Chunks along the first dimension (frames) of about opt.chunk_bytes.
    std::vector<hsize_t> chunk(hd);
    std::size_t row_bytes = product(dims, 1) * elem_size;
    chunk[0] = std::clamp<hsize_t>(opt.chunk_bytes / std::max<std::size_t>(row_bytes, 1), 1, hd[0]);
    if (row_bytes > 4 * opt.chunk_bytes && hd.size() >= 2) {
      std::size_t sub_bytes = row_bytes / std::max<hsize_t>(hd[1], 1);
      chunk[1] =
          std::clamp<hsize_t>(opt.chunk_bytes / std::max<std::size_t>(sub_bytes, 1), 1, hd[1]);
    }
    check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()),
          "cannot set chunking", where(path));
    check(H5Pset_shuffle(dcpl.get()), "cannot set shuffle", where(path));
    unsigned level = static_cast<unsigned>(opt.zstd_level);
    check(H5Pset_filter(dcpl.get(), kZstdFilterId, H5Z_FLAG_OPTIONAL, 1, &level),
          "cannot set the zstd filter", where(path));
  }
  return checked(H5Dcreate2(file_.get(), path.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(),
                            H5P_DEFAULT),
                 H5Dclose, "cannot create dataset", where(path));
}

template <class T>
void File::write(const std::string& path, std::span<const T> data,
                 const std::vector<std::size_t>& dims, const StorageOptions& opt) {
  if (product(dims) != data.size())
    throw Error("internal: data size does not match the dataset shape", where(path));
  Handle ds = make_dataset(path, native_type<T>(), dims, sizeof(T), opt);
  if (!data.empty())
    check(H5Dwrite(ds.get(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()),
          "cannot write dataset", where(path));
}

template <class T>
void File::create(const std::string& path, const std::vector<std::size_t>& dims,
                  const StorageOptions& opt) {
  make_dataset(path, native_type<T>(), dims, sizeof(T), opt);
}

void File::write_strings(const std::string& path, const std::vector<std::string>& values) {
  Handle type = utf8_string_type();
  StorageOptions plain;
  plain.compress = false;
  Handle ds = make_dataset(path, type.get(), {values.size()}, sizeof(char*), plain);
  std::vector<const char*> ptrs;
  for (const auto& s : values) ptrs.push_back(s.c_str());
  if (!ptrs.empty())
    check(H5Dwrite(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()),
          "cannot write strings", where(path));
}

std::vector<std::string> File::read_strings(const std::string& path) const {
  Handle ds = open_dataset(path);
  Handle type(H5Dget_type(ds.get()), H5Tclose);
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  if (H5Tget_class(type.get()) != H5T_STRING)
    throw InvalidInput("dataset is not of strings", where(path));
  std::size_t n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
  return read_string_values(
      type.get(), n,
      [&](hid_t mem, void* buf) {
        return H5Dread(ds.get(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
      },
      where(path));
}

template <class T>
Array<T> File::read(const std::string& path) const {
  Handle ds = open_dataset(path);
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  Array<T> a;
  a.dims = space_dims(space.get());
  a.data.resize(product(a.dims));
  if (!a.data.empty())
    check(H5Dread(ds.get(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, a.data.data()),
          "cannot read dataset", where(path));
  return a;
}

template <class T>
RowMatrix<T> File::read_matrix(const std::string& path) const {
  Array<T> a = read<T>(path);
  if (a.dims.size() > 2) throw InvalidInput("expected a matrix (rank 2)", where(path));
  Eigen::Index rows = a.dims.empty() ? 1 : static_cast<Eigen::Index>(a.dims[0]);
  Eigen::Index cols = a.dims.size() == 2 ? static_cast<Eigen::Index>(a.dims[1]) : 1;
  return Eigen::Map<const RowMatrix<T>>(a.data.data(), rows, cols);
}

namespace {
struct Slab {
  Handle file_space, mem_space;
};
Slab select_rows(hid_t ds, std::size_t first, std::size_t count, const std::string& where) {
  Slab s;
  s.file_space = Handle(H5Dget_space(ds), H5Sclose);
  auto dims = space_dims(s.file_space.get());
  if (dims.empty() || first + count > dims[0])
    throw Error("internal: rows " + std::to_string(first) + "+" + std::to_string(count) +
                    " outside the dataset",
                where);
  std::vector<hsize_t> start(dims.size(), 0), cnt(dims.begin(), dims.end());
  start[0] = first;
  cnt[0] = count;
  check(H5Sselect_hyperslab(s.file_space.get(), H5S_SELECT_SET, start.data(), nullptr, cnt.data(),
                            nullptr),
        "cannot select rows", where);
  s.mem_space =
      Handle(H5Screate_simple(static_cast<int>(cnt.size()), cnt.data(), nullptr), H5Sclose);
  return s;
}

// --- parallel chunk I/O
// Datasets this library writes (chunks of whole rows, filters exactly shuffle + zstd) are
// read and written chunk by chunk with H5Dread_chunk/H5Dwrite_chunk, with the byte shuffle
// and zstd (de)compression of the chunks done in parallel. All HDF5 calls stay on the calling
// thread (the serial HDF5 library is not thread-safe); the bytes are exactly what the filter
// pipeline would produce, so h5dump and the plugin read them as usual.
struct ChunkLayout {
  bool direct = false;
  std::vector<std::size_t> dims;
  std::size_t chunk_rows = 0, row_elems = 0;
  int zstd_level = 3;
};

ChunkLayout chunk_layout(hid_t ds) {
  ChunkLayout L;
  Handle dcpl(H5Dget_create_plist(ds), H5Pclose);
  Handle space(H5Dget_space(ds), H5Sclose);
  L.dims = space_dims(space.get());
  if (L.dims.empty() || H5Pget_layout(dcpl.get()) != H5D_CHUNKED ||
      H5Pget_nfilters(dcpl.get()) != 2)
    return L;
  unsigned flags = 0, cd[4] = {0, 0, 0, 0}, config = 0;
  std::size_t ncd = 4;
  if (H5Pget_filter2(dcpl.get(), 0, &flags, &ncd, cd, 0, nullptr, &config) != H5Z_FILTER_SHUFFLE)
    return L;
  ncd = 4;
  if (H5Pget_filter2(dcpl.get(), 1, &flags, &ncd, cd, 0, nullptr, &config) != kZstdFilterId)
    return L;
  L.zstd_level = ncd > 0 ? static_cast<int>(cd[0]) : 3;
  std::vector<hsize_t> chunk(L.dims.size());
  if (H5Pget_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()) < 0) return L;
  L.row_elems = product(L.dims, 1);
  for (std::size_t k = 1; k < L.dims.size(); ++k)
    if (chunk[k] != L.dims[k]) return L;  // chunks split a row: use the filter pipeline
  L.chunk_rows = chunk[0];
  L.direct = L.chunk_rows > 0 && L.row_elems > 0;
  return L;
}

// HDF5's byte shuffle: byte j of element i goes to out[j·n + i] (shuffle), or back from there
// (unshuffle). Element-major loops with a compile-time element size for the common sizes
// (sequential reads, `size` sequential write streams).
enum class ByteOrder { shuffle, unshuffle };
template <ByteOrder Way, std::size_t S>
void reorder_fixed(const unsigned char* in, unsigned char* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < S; ++j)
      if constexpr (Way == ByteOrder::shuffle)
        out[j * n + i] = in[i * S + j];
      else
        out[i * S + j] = in[j * n + i];
}
template <ByteOrder Way>
void reorder_bytes(const unsigned char* in, unsigned char* out, std::size_t n, std::size_t size) {
  switch (size) {
    case 8:
      return reorder_fixed<Way, 8>(in, out, n);
    case 4:
      return reorder_fixed<Way, 4>(in, out, n);
    case 2:
      return reorder_fixed<Way, 2>(in, out, n);
    default:
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < size; ++j)
          if constexpr (Way == ByteOrder::shuffle)
            out[j * n + i] = in[i * size + j];
          else
            out[i * size + j] = in[j * n + i];
  }
}

// Per-thread zstd contexts and scratch buffers: creating a context per chunk (what
// ZSTD_compress does) costs allocations and page faults comparable to the compression itself.
struct Scratch {
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  ZSTD_DCtx* dctx = ZSTD_createDCtx();
  std::vector<unsigned char> bytes;
  ~Scratch() {
    ZSTD_freeCCtx(cctx);
    ZSTD_freeDCtx(dctx);
  }
  Scratch() = default;
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
};
Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

}  // namespace

// Splits rows [first, first+count) into a partial head, whole chunks (the last may run past the
// dataset's end) and a partial tail: the head and tail go through HDF5's own pipeline, the
// whole chunks through the parallel path.
struct RowSplit {
  std::size_t head = 0, middle = 0;  // rows; tail = count - head - middle
};
RowSplit split_rows(const ChunkLayout& L, std::size_t first, std::size_t count) {
  RowSplit r;
  if (!L.direct) {
    r.head = count;
    return r;
  }
  const std::size_t cr = L.chunk_rows, n = L.dims[0];
  std::size_t start = (first + cr - 1) / cr * cr;  // first chunk boundary at or after first
  r.head = std::min(count, start - first);
  std::size_t end = first + count;
  std::size_t stop = end == n ? end : end / cr * cr;  // up to the dataset's end, or a boundary
  if (stop > start) r.middle = stop - start;
  if (r.middle < 2 * cr) r.middle = 0, r.head = count;  // too little to be worth it
  return r;
}

template <class T>
void File::write_rows(const std::string& path, std::size_t first, std::size_t count,
                      const T* data) {
  Handle ds = open_dataset(path);
  ChunkLayout L = chunk_layout(ds.get());
  RowSplit sp = split_rows(L, first, count);
  auto pipeline_write = [&](std::size_t f0, std::size_t n) {
    if (!n) return;
    Slab s = select_rows(ds.get(), f0, n, where(path));
    check(H5Dwrite(ds.get(), native_type<T>(), s.mem_space.get(), s.file_space.get(), H5P_DEFAULT,
                   data + (f0 - first) * product(L.dims, 1)),
          "cannot write rows", where(path));
  };
  pipeline_write(first, sp.head);
  if (sp.middle) {
    const std::size_t m0 = first + sp.head;
    const T* mdata = data + sp.head * L.row_elems;
    const std::size_t n_chunks = (sp.middle + L.chunk_rows - 1) / L.chunk_rows;
    const std::size_t chunk_elems = L.chunk_rows * L.row_elems,
                      chunk_bytes = chunk_elems * sizeof(T);
    std::vector<std::vector<unsigned char>> packed(n_chunks);
    std::vector<char> failed(n_chunks, 0);
    tbb::parallel_for(std::size_t{0}, n_chunks, [&](std::size_t c) {
      std::size_t rows = std::min(L.chunk_rows, sp.middle - c * L.chunk_rows);
      const T* src = mdata + c * chunk_elems;
      std::vector<T> padded;  // an edge chunk is padded to full size
      if (rows < L.chunk_rows) {
        padded.assign(chunk_elems, T{});
        std::copy(src, src + rows * L.row_elems, padded.begin());
        src = padded.data();
      }
      Scratch& sc = scratch();
      sc.bytes.resize(chunk_bytes);
      reorder_bytes<ByteOrder::shuffle>(reinterpret_cast<const unsigned char*>(src),
                                        sc.bytes.data(), chunk_elems, sizeof(T));
      packed[c].resize(ZSTD_compressBound(chunk_bytes));
      std::size_t n = ZSTD_compressCCtx(sc.cctx, packed[c].data(), packed[c].size(),
                                        sc.bytes.data(), chunk_bytes, L.zstd_level);
      if (ZSTD_isError(n))
        failed[c] = 1;
      else
        packed[c].resize(n);
    });
    for (std::size_t c = 0; c < n_chunks; ++c) {
      if (failed[c]) throw IOError("zstd compression failed", where(path));
      std::vector<hsize_t> offset(L.dims.size(), 0);
      offset[0] = m0 + c * L.chunk_rows;
      check(H5Dwrite_chunk(ds.get(), H5P_DEFAULT, 0, offset.data(), packed[c].size(),
                           packed[c].data()),
            "cannot write chunk", where(path));
    }
  }
  pipeline_write(first + sp.head + sp.middle, count - sp.head - sp.middle);
}

template <class T>
void File::read_rows(const std::string& path, std::size_t first, std::size_t count, T* data) const {
  Handle ds = open_dataset(path);
  ChunkLayout L = chunk_layout(ds.get());
  Handle type(H5Dget_type(ds.get()), H5Tclose);
  RowSplit sp = split_rows(L, first, count);
  if (H5Tequal(type.get(), native_type<T>()) <= 0) sp = RowSplit{count, 0};  // needs conversion
  auto pipeline_read = [&](std::size_t f0, std::size_t n) {
    if (!n) return;
    Slab s = select_rows(ds.get(), f0, n, where(path));
    check(H5Dread(ds.get(), native_type<T>(), s.mem_space.get(), s.file_space.get(), H5P_DEFAULT,
                  data + (f0 - first) * product(L.dims, 1)),
          "cannot read rows", where(path));
  };
  pipeline_read(first, sp.head);
  if (sp.middle) {
    const std::size_t m0 = first + sp.head;
    T* mdata = data + sp.head * L.row_elems;
    const std::size_t n_chunks = (sp.middle + L.chunk_rows - 1) / L.chunk_rows;
    const std::size_t chunk_elems = L.chunk_rows * L.row_elems,
                      chunk_bytes = chunk_elems * sizeof(T);
    std::vector<std::vector<unsigned char>> packed(n_chunks);
    std::vector<std::uint32_t> mask(n_chunks, 0);
    for (std::size_t c = 0; c < n_chunks; ++c) {
      std::vector<hsize_t> offset(L.dims.size(), 0);
      offset[0] = m0 + c * L.chunk_rows;
      hsize_t nbytes = 0;
      check(H5Dget_chunk_storage_size(ds.get(), offset.data(), &nbytes), "cannot locate chunk",
            where(path));
      packed[c].resize(nbytes);
      if (nbytes)
        check(H5Dread_chunk(ds.get(), H5P_DEFAULT, offset.data(), &mask[c], packed[c].data()),
              "cannot read chunk", where(path));
    }
    std::vector<char> failed(n_chunks, 0);
    tbb::parallel_for(std::size_t{0}, n_chunks, [&](std::size_t c) {
      std::size_t rows = std::min(L.chunk_rows, sp.middle - c * L.chunk_rows);
      T* dst = mdata + c * chunk_elems;
      if (packed[c].empty()) {  // never written: the fill value
        std::fill(dst, dst + rows * L.row_elems, T{});
        return;
      }
      Scratch& sc = scratch();
      const unsigned char* shuffled = packed[c].data();
      if (!(mask[c] & 2u)) {  // zstd applied
        sc.bytes.resize(chunk_bytes);
        std::size_t n = ZSTD_decompressDCtx(sc.dctx, sc.bytes.data(), chunk_bytes, packed[c].data(),
                                            packed[c].size());
        if (ZSTD_isError(n) || n != chunk_bytes) {
          failed[c] = 1;
          return;
        }
        shuffled = sc.bytes.data();
      } else if (packed[c].size() != chunk_bytes) {
        failed[c] = 1;
        return;
      }
      std::vector<T> padded;  // an edge chunk decodes to full size; keep its rows
      T* out = dst;
      if (rows < L.chunk_rows) {
        padded.resize(chunk_elems);
        out = padded.data();
      }
      if (!(mask[c] & 1u))
        reorder_bytes<ByteOrder::unshuffle>(shuffled, reinterpret_cast<unsigned char*>(out),
                                            chunk_elems, sizeof(T));
      else
        std::memcpy(out, shuffled, chunk_bytes);
      if (out != dst)
        std::copy(padded.begin(), padded.begin() + static_cast<std::ptrdiff_t>(rows * L.row_elems),
                  dst);
    });
    for (char f : failed)
      if (f) throw IOError("corrupt compressed chunk", where(path));
  }
  pipeline_read(first + sp.head + sp.middle, count - sp.head - sp.middle);
}

#define DF_H5_INSTANTIATE(T)                                                                 \
  template void File::write<T>(const std::string&, std::span<const T>,                       \
                               const std::vector<std::size_t>&, const StorageOptions&);      \
  template void File::create<T>(const std::string&, const std::vector<std::size_t>&,         \
                                const StorageOptions&);                                      \
  template Array<T> File::read<T>(const std::string&) const;                                 \
  template RowMatrix<T> File::read_matrix<T>(const std::string&) const;                      \
  template void File::write_rows<T>(const std::string&, std::size_t, std::size_t, const T*); \
  template void File::read_rows<T>(const std::string&, std::size_t, std::size_t, T*) const;

DF_H5_INSTANTIATE(float)
DF_H5_INSTANTIATE(double)
DF_H5_INSTANTIATE(std::int8_t)
DF_H5_INSTANTIATE(std::uint8_t)
DF_H5_INSTANTIATE(std::int32_t)
DF_H5_INSTANTIATE(std::uint32_t)
DF_H5_INSTANTIATE(std::int64_t)
DF_H5_INSTANTIATE(std::uint64_t)
#undef DF_H5_INSTANTIATE

}  // namespace df::h5
