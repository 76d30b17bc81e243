// A thin RAII layer over the HDF5 C API. Objects are addressed by absolute paths
// ("/frames/positions"); every failing call becomes an IOError naming the file and object,
// and HDF5's own error-stack printing is switched off. Writes create missing groups, track no
// object timestamps (identical data => identical bytes) and, for datasets above a few KiB,
// use chunks + byte shuffle + zstd (filter 32015).
#pragma once

#include <hdf5.h>

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace df::h5 {

/// Row-major dense matrix: the memory layout of HDF5 datasets.
template <class T>
using RowMatrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// An n-dimensional array in row-major order (e.g. [N,V,9] features).
template <class T>
struct Array {
  std::vector<std::size_t> dims;
  std::vector<T> data;
  std::size_t size() const { return data.size(); }
};

/// Element types the project stores.
enum class Dtype { f32, f64, i8, u8, i32, u32, i64, u64, string, other };
const char* dtype_name(Dtype t);
Dtype dtype_from_name(const std::string& name);  ///< "float32" ... ; other if unknown

struct DatasetInfo {
  Dtype dtype = Dtype::other;
  std::vector<std::size_t> dims;
  std::vector<int> filters;  ///< filter ids of the pipeline, in order
  /// Whether the file stores all of the data (false: a shape declared with chunks never
  /// written, which reads as fill values; deformflow never writes such datasets).
  bool fully_stored = true;
};

/// How a dataset is stored.
struct StorageOptions {
  bool compress = true;               ///< chunk + shuffle + zstd when the data exceeds 4 KiB
  int zstd_level = 1;                 ///< level 3 took twice as long for 0.6% smaller feature files
  std::size_t chunk_bytes = 1 << 20;  ///< target chunk size
};

/// Owns one hid_t and closes it with the matching H5?close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), close_(closer) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      close_ = o.close_;
      o.id_ = H5I_INVALID_HID;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  explicit operator bool() const { return id_ >= 0; }
  /// Gives up ownership without closing.
  hid_t release() {
    hid_t id = id_;
    id_ = H5I_INVALID_HID;
    return id;
  }
  void reset() {
    if (id_ >= 0 && close_) close_(id_);
    id_ = H5I_INVALID_HID;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

/// Switches off HDF5's error printing and registers the zstd filter; idempotent. Called by
/// File's constructors, so users rarely need it.
void initialize();

/// An open HDF5 file. `display_name` is what error messages show (e.g. the final output path
/// while writing a temporary).
class File {
 public:
  enum class Mode { read, read_write, create };
  File(const std::filesystem::path& path, Mode mode, std::string display_name = {});

  const std::string& name() const { return name_; }
  hid_t id() const { return file_.get(); }
  /// Flushes and closes; errors become exceptions (the destructor would swallow them).
  void close();

  // --- structure
  bool exists(const std::string& path) const;  ///< object at path (intermediate groups checked)
  bool is_group(const std::string& path) const;
  bool is_dataset(const std::string& path) const;
  /// Names of the children of a group, sorted.
  std::vector<std::string> children(const std::string& group) const;
  /// Absolute paths of every group and dataset below `group`, depth first, children sorted.
  std::vector<std::string> descendants(const std::string& group = "/") const;
  void create_groups(const std::string& path);  ///< like mkdir -p
  DatasetInfo info(const std::string& dataset) const;

  // --- attributes (on a group or dataset; "/" = root)
  bool has_attr(const std::string& object, const std::string& name) const;
  std::vector<std::string> attr_names(const std::string& object) const;
  void set_attr(const std::string& object, const std::string& name, const std::string& value);
  void set_attr(const std::string& object, const std::string& name, const char* value) {
    set_attr(object, name, std::string(value));
  }
  void set_attr(const std::string& object, const std::string& name, double value);
  void set_attr(const std::string& object, const std::string& name, std::int64_t value);
  void set_attr(const std::string& object, const std::string& name, int value) {
    set_attr(object, name, static_cast<std::int64_t>(value));
  }
  void set_attr(const std::string& object, const std::string& name, std::span<const double> v);
  std::string attr_string(const std::string& object, const std::string& name) const;
  double attr_double(const std::string& object, const std::string& name) const;
  std::int64_t attr_int(const std::string& object, const std::string& name) const;
  std::vector<double> attr_doubles(const std::string& object, const std::string& name) const;

  // --- whole datasets
  template <class T>
  void write(const std::string& path, std::span<const T> data, const std::vector<std::size_t>& dims,
             const StorageOptions& opt = {});
  template <class T>
  void write(const std::string& path, const Array<T>& a, const StorageOptions& opt = {}) {
    write<T>(path, std::span<const T>(a.data), a.dims, opt);
  }
  /// Writes an Eigen matrix (any storage order) as a rank-2 dataset [rows, cols].
  template <class Derived>
  void write_matrix(const std::string& path, const Eigen::DenseBase<Derived>& m,
                    const StorageOptions& opt = {}) {
    using T = typename Derived::Scalar;
    RowMatrix<T> r = m;
    write<T>(path, std::span<const T>(r.data(), static_cast<std::size_t>(r.size())),
             {static_cast<std::size_t>(r.rows()), static_cast<std::size_t>(r.cols())}, opt);
  }
  void write_strings(const std::string& path, const std::vector<std::string>& values);

  template <class T>
  Array<T> read(const std::string& path) const;
  /// Reads a rank-2 dataset (or rank-1 as a column).
  template <class T>
  RowMatrix<T> read_matrix(const std::string& path) const;
  std::vector<std::string> read_strings(const std::string& path) const;

  // --- partial I/O along the first dimension (frames), for streaming large arrays
  /// Creates an empty dataset of the given shape (chunked/compressed per opt).
  template <class T>
  void create(const std::string& path, const std::vector<std::size_t>& dims,
              const StorageOptions& opt = {});
  /// Writes rows [first, first+count) of the first dimension.
  template <class T>
  void write_rows(const std::string& path, std::size_t first, std::size_t count, const T* data);
  /// Reads rows [first, first+count) of the first dimension into data (prod(dims[1:])*count).
  template <class T>
  void read_rows(const std::string& path, std::size_t first, std::size_t count, T* data) const;

  /// Builds "file/object" for messages.
  std::string where(const std::string& object) const;

 private:
  Handle open_object(const std::string& path) const;
  Handle open_dataset(const std::string& path) const;
  Handle make_dataset(const std::string& path, hid_t type, const std::vector<std::size_t>& dims,
                      std::size_t elem_size, const StorageOptions& opt);
  void write_attr_raw(const std::string& object, const std::string& name, hid_t type, hid_t space,
                      const void* data);

  std::string name_;
  Handle file_;
};

/// The HDF5 native memory type of T.
template <class T>
hid_t native_type();

}  // namespace df::h5
