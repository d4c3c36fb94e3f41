#pragma once
// Thin helpers over the HDF5 C API shared by the io/*.cpp files (private to io/): an
// owning handle and typed access to datasets and attributes. Helpers throw
// std::runtime_error saying only what failed ("dataset /positions missing"); the callers
// add the file's path and kind, which the helpers do not know.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <hdf5.h>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace capsim::h5 {

// The descriptions on HDF5's error stack after a failed call, innermost first, joined by
// newlines (HDF5 does not print them: silence_errors()).
inline std::string error_stack() {
  std::string text;
  auto visit = [](unsigned, const H5E_error2_t* e, void* out) -> herr_t {
    if (e->desc)
      *static_cast<std::string*>(out) += std::string(e->desc) + "\n";
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, visit, &text);
  return text;
}

// The operating system's reason for the HDF5 call that just failed ("No space left on
// device"): HDF5 keeps errno only as text in its error stack, "..., errno = 28, error
// message = 'No space left on device', ...". Empty when no system call failed.
inline std::string system_reason() {
  static const std::string key = "error message = '";
  const std::string stack = error_stack();
  const std::size_t start = stack.find(key);
  if (start == std::string::npos)
    return "";
  const std::size_t from = start + key.size();
  return stack.substr(from, stack.find('\'', from) - from);
}

// `what` failed, with the reason when HDF5 knows one: the system's (a full disk), or a
// checksum that does not match (damaged data).
inline std::string failure(const std::string& what) {
  const std::string reason = system_reason();
  if (!reason.empty())
    return what + ": " + reason;
  if (error_stack().find("checksum") != std::string::npos)
    return what + ": a checksum does not match (the data are damaged)";
  return what;
}

// Owns one HDF5 identifier. H5Idec_ref closes any kind of object (file, dataset, ...)
// once its count reaches zero, so one class serves them all.
class Handle {
public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  ~Handle() { reset(); }
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, -1)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, -1);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  hid_t get() const { return id_; }
  void reset() {
    if (id_ >= 0)
      H5Idec_ref(id_);
    id_ = -1;
  }
  // Closes now and reports failure: closing a file is where HDF5 writes its buffers.
  void close(const std::string& what) {
    const hid_t id = std::exchange(id_, -1);
    if (id >= 0 && H5Idec_ref(id) < 0)
      throw std::runtime_error(failure("cannot close " + what));
  }

private:
  hid_t id_ = -1;
};

inline Handle check(hid_t id, const std::string& what) {
  if (id < 0)
    throw std::runtime_error(failure(what));
  return Handle(id);
}

inline void check_status(herr_t status, const std::string& what) {
  if (status < 0)
    throw std::runtime_error(failure(what));
}

// HDF5 prints its whole error stack to stderr by default; users should see only our
// message, so every entry point that opens or creates a file turns that off. It also
// keeps HDF5 from closing, at exit, objects whose close already failed (a full disk):
// HDF5 1.10 crashes there. Every file is closed explicitly, so nothing is lost; this
// takes effect only before the library's first call, which this is.
inline void silence_errors() {
  H5dont_atexit();
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

// Element types: native layout in memory, fixed little-endian layout in the file.
template <class T> struct Type;
template <> struct Type<double> {
  static hid_t memory() { return H5T_NATIVE_DOUBLE; }
  static hid_t file() { return H5T_IEEE_F64LE; }
};
template <> struct Type<std::int64_t> {
  static hid_t memory() { return H5T_NATIVE_INT64; }
  static hid_t file() { return H5T_STD_I64LE; }
};
template <> struct Type<std::int32_t> {
  static hid_t memory() { return H5T_NATIVE_INT32; }
  static hid_t file() { return H5T_STD_I32LE; }
};

using Dims = std::vector<hsize_t>;

inline std::string shape_string(const Dims& dims) {
  std::string s = "(";
  for (std::size_t i = 0; i < dims.size(); ++i)
    s += (i ? ", " : "") + std::to_string(dims[i]);
  return s + ")";
}

inline hsize_t element_count(const Dims& dims) {
  hsize_t n = 1;
  for (hsize_t d : dims)
    n *= d;
  return n;
}

// Files use the HDF5 1.10 format, whose headers and chunk indexes carry checksums (those
// of 1.8 leave the chunk index unchecked), so a damaged file is found when read; readers
// of HDF5 1.10 and later (h5py, ParaView) open it.
inline Handle create_file(const std::string& path) {
  silence_errors();
  Handle access = check(H5Pcreate(H5P_FILE_ACCESS), "cannot create a file access list");
  check_status(H5Pset_libver_bounds(access.get(), H5F_LIBVER_V110, H5F_LIBVER_V110),
               "cannot choose the file format");
  const hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get());
  if (id >= 0)
    return Handle(id);
  const std::string reason = system_reason();
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
    throw std::runtime_error("folder " + folder.string() + " does not exist");
  if (!reason.empty())
    throw std::runtime_error("cannot create the file: " + reason);
  throw std::runtime_error("cannot create the file (folder not writable, or file open)");
}

// `flags` is H5F_ACC_RDONLY or H5F_ACC_RDWR.
inline Handle open_file(const std::string& path, unsigned flags) {
  silence_errors();
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw std::runtime_error("not an HDF5 file");
  const hid_t id = H5Fopen(path.c_str(), flags, H5P_DEFAULT);
  if (id >= 0)
    return Handle(id);
  const std::string stack = error_stack(), reason = system_reason();
  if (stack.find("truncated file") != std::string::npos)
    throw std::runtime_error("the file is truncated (shorter than its HDF5 header says)");
  throw std::runtime_error("the HDF5 file cannot be opened" +
                           (reason.empty() ? std::string(" (damaged)") : ": " + reason));
}

// Runs `read` on an existing file; any failure comes back as
// "<kind> <path> is corrupt or not a capsim <kind>: <what failed>".
template <class Read>
auto read_or_explain(const std::string& kind, const std::string& path, Read&& read) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw std::runtime_error(kind + " " + path + " does not exist");
  try {
    return read();
  } catch (const std::exception& e) { // also bad_alloc from absurd sizes in a bad file
    throw std::runtime_error(kind + " " + path + " is corrupt or not a capsim " + kind +
                             ": " + e.what());
  }
}

inline Handle make_space(const Dims& dims) {
  const hid_t id = dims.empty() ? H5Screate(H5S_SCALAR)
                                : H5Screate_simple(static_cast<int>(dims.size()),
                                                   dims.data(), nullptr);
  return check(id, "cannot create a dataspace");
}

inline Handle open_dataset(hid_t loc, const std::string& name) {
  // H5Lexists fails (< 0) when a parent group is missing: that is "missing" too.
  if (H5Lexists(loc, name.c_str(), H5P_DEFAULT) <= 0)
    throw std::runtime_error("dataset " + name + " missing");
  return check(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), "cannot open dataset " + name);
}

inline Dims dataset_dims(hid_t dataset, const std::string& name) {
  Handle space = check(H5Dget_space(dataset), "cannot read the shape of " + name);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0)
    throw std::runtime_error("cannot read the shape of " + name);
  Dims dims(rank);
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return dims;
}

template <class T>
void write_dataset(hid_t loc, const std::string& name, const Dims& dims, const T* data) {
  Handle space = make_space(dims);
  Handle dataset = check(H5Dcreate2(loc, name.c_str(), Type<T>::file(), space.get(),
                                    H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                         "cannot create dataset " + name);
  // H5Dwrite rejects a null buffer even when there is nothing to write.
  if (element_count(dims) == 0)
    return;
  check_status(
      H5Dwrite(dataset.get(), Type<T>::memory(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
      "cannot write dataset " + name);
}

template <class T> void write_scalar(hid_t loc, const std::string& name, T value) {
  write_dataset(loc, name, {}, &value);
}

// Reads a dataset of any shape; its shape is returned in `dims`.
template <class T>
std::vector<T> read_any_shape(hid_t loc, const std::string& name, Dims& dims) {
  Handle dataset = open_dataset(loc, name);
  dims = dataset_dims(dataset.get(), name);
  std::vector<T> data(element_count(dims));
  if (!data.empty())
    check_status(H5Dread(dataset.get(), Type<T>::memory(), H5S_ALL, H5S_ALL, H5P_DEFAULT,
                         data.data()),
                 "cannot read dataset " + name);
  return data;
}

template <class T>
std::vector<T> read_dataset(hid_t loc, const std::string& name, const Dims& expected) {
  Dims dims;
  std::vector<T> data = read_any_shape<T>(loc, name, dims);
  if (dims != expected)
    throw std::runtime_error("dataset " + name + " has shape " + shape_string(dims) +
                             ", expected " + shape_string(expected));
  return data;
}

template <class T> T read_scalar(hid_t loc, const std::string& name) {
  return read_dataset<T>(loc, name, {})[0];
}

template <class T> void write_attribute(hid_t obj, const std::string& name, T value) {
  Handle space = make_space({});
  Handle attr = check(H5Acreate2(obj, name.c_str(), Type<T>::file(), space.get(),
                                 H5P_DEFAULT, H5P_DEFAULT),
                      "cannot create attribute " + name);
  check_status(H5Awrite(attr.get(), Type<T>::memory(), &value),
               "cannot write attribute " + name);
}

template <class T> T read_attribute(hid_t obj, const std::string& name) {
  if (H5Aexists(obj, name.c_str()) <= 0)
    throw std::runtime_error("attribute " + name + " missing");
  Handle attr =
      check(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "cannot open attribute " + name);
  T value{};
  check_status(H5Aread(attr.get(), Type<T>::memory(), &value),
               "cannot read attribute " + name);
  return value;
}

// Variable-length UTF-8 strings: no length limit, and h5py returns them as str.
inline Handle string_type() {
  Handle type = check(H5Tcopy(H5T_C_S1), "cannot create a string type");
  check_status(H5Tset_size(type.get(), H5T_VARIABLE), "cannot create a string type");
  check_status(H5Tset_cset(type.get(), H5T_CSET_UTF8), "cannot create a string type");
  return type;
}

inline void write_string_attribute(hid_t obj, const std::string& name,
                                   const std::string& value) {
  Handle type = string_type();
  Handle space = make_space({});
  Handle attr = check(
      H5Acreate2(obj, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
      "cannot create attribute " + name);
  const char* text = value.c_str();
  check_status(H5Awrite(attr.get(), type.get(), &text), "cannot write attribute " + name);
}

inline std::string read_string_attribute(hid_t obj, const std::string& name) {
  if (H5Aexists(obj, name.c_str()) <= 0)
    throw std::runtime_error("attribute " + name + " missing");
  Handle attr =
      check(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "cannot open attribute " + name);
  Handle type = string_type();
  char* text = nullptr;
  check_status(H5Aread(attr.get(), type.get(), &text),
               "cannot read attribute " + name + " as a string");
  std::string value = text ? text : "";
  H5free_memory(text); // HDF5 allocated it for the variable-length read
  return value;
}

inline void write_string_dataset(hid_t loc, const std::string& name,
                                 const std::string& value) {
  Handle type = string_type();
  Handle space = make_space({});
  Handle dataset = check(H5Dcreate2(loc, name.c_str(), type.get(), space.get(),
                                    H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                         "cannot create dataset " + name);
  const char* text = value.c_str();
  check_status(H5Dwrite(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &text),
               "cannot write dataset " + name);
}

inline std::string read_string_dataset(hid_t loc, const std::string& name) {
  Handle dataset = open_dataset(loc, name);
  if (!dataset_dims(dataset.get(), name).empty())
    throw std::runtime_error("dataset " + name + " is not a scalar string");
  Handle type = string_type();
  char* text = nullptr;
  check_status(H5Dread(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &text),
               "cannot read dataset " + name + " as a string");
  std::string value = text ? text : "";
  H5free_memory(text); // HDF5 allocated it for the variable-length read
  return value;
}

} // namespace capsim::h5
