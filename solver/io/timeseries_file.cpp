#include "io/timeseries_file.hpp"

#include "io/hdf5_util.hpp"
#include "io/kill_point.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace capsim {
namespace {

// A chunk of at most 64 rows and about 256 KiB stays inside HDF5's default 1 MiB chunk
// cache, so appending a row does not rewrite a whole chunk from disk each time.
constexpr hsize_t kMaxChunkRows = 64;
constexpr hsize_t kTargetChunkBytes = 256 * 1024;

// One per-capsule column of /capsule: dataset name, units, the shape of one capsule's
// entry, and how that entry is copied out of and back into a CapsuleSample.
struct CapsuleColumn {
  const char* name;
  const char* units;
  h5::Dims shape;
  void (*get)(const CapsuleSample&, double*);
  void (*set)(CapsuleSample&, const double*);
  // Added after files were first written: an older file lacks it, reads it as zeros,
  // and gains it (zeros for the rows it holds) when a run resumes.
  bool added_later = false;
};

template <double CapsuleSample::*field>
void get_scalar(const CapsuleSample& c, double* v) {
  v[0] = c.*field;
}
template <double CapsuleSample::*field>
void set_scalar(CapsuleSample& c, const double* v) {
  c.*field = v[0];
}
void get_centroid(const CapsuleSample& c, double* v) {
  v[0] = c.centroid.x, v[1] = c.centroid.y, v[2] = c.centroid.z;
}
void set_centroid(CapsuleSample& c, const double* v) {
  c.centroid = {v[0], v[1], v[2]};
}
void get_stresslet(const CapsuleSample& c, double* v) {
  for (int k = 0; k < 9; ++k)
    v[k] = c.stresslet.m[k / 3][k % 3];
}
void set_stresslet(CapsuleSample& c, const double* v) {
  for (int k = 0; k < 9; ++k)
    c.stresslet.m[k / 3][k % 3] = v[k];
}

template <double CapsuleSample::*field>
CapsuleColumn scalar(const char* name, const char* units, bool added_later = false) {
  return {name, units, {}, get_scalar<field>, set_scalar<field>, added_later};
}

const std::vector<CapsuleColumn>& capsule_columns() {
  static const std::vector<CapsuleColumn> columns = {
      scalar<&CapsuleSample::taylor_D>("D", "1"),
      scalar<&CapsuleSample::theta_D_deg>("theta_D_deg", "deg"),
      scalar<&CapsuleSample::principal_diff>("principal_diff", "Gs a^2"),
      scalar<&CapsuleSample::theta_S_deg>("theta_S_deg", "deg"),
      scalar<&CapsuleSample::energy>("energy", "Gs a^2"),
      scalar<&CapsuleSample::volume_error>("volume_error", "1"),
      scalar<&CapsuleSample::volume_drift>("volume_drift", "1"),
      scalar<&CapsuleSample::repelled_nodes>("repelled_nodes", "1", true),
      scalar<&CapsuleSample::compressed_elements>("compressed_elements", "1", true),
      scalar<&CapsuleSample::min_tension>("min_tension", "Gs", true),
      {"stresslet", "Gs a^2", {3, 3}, get_stresslet, set_stresslet},
      {"centroid", "a", {3}, get_centroid, set_centroid},
  };
  return columns;
}

std::string column_path(const CapsuleColumn& column) {
  return std::string("/capsule/") + column.name;
}

// Shape of one row of a column's dataset: (M, shape...).
h5::Dims row_shape(const CapsuleColumn& column, int num_capsules) {
  h5::Dims dims{static_cast<hsize_t>(num_capsules)};
  dims.insert(dims.end(), column.shape.begin(), column.shape.end());
  return dims;
}

template <class T>
h5::Handle create_extendible(hid_t loc, const std::string& name, const h5::Dims& row,
                             const char* units) {
  h5::Dims dims{0}, max_dims{H5S_UNLIMITED}, chunk{1};
  dims.insert(dims.end(), row.begin(), row.end());
  max_dims.insert(max_dims.end(), row.begin(), row.end());
  chunk.insert(chunk.end(), row.begin(), row.end());
  const hsize_t row_bytes = sizeof(T) * h5::element_count(row);
  chunk[0] = std::clamp<hsize_t>(kTargetChunkBytes / row_bytes, 1, kMaxChunkRows);

  const int rank = static_cast<int>(dims.size());
  h5::Handle space = h5::check(H5Screate_simple(rank, dims.data(), max_dims.data()),
                               "cannot create a dataspace");
  h5::Handle plist = h5::check(H5Pcreate(H5P_DATASET_CREATE), "cannot create a plist");
  h5::check_status(H5Pset_chunk(plist.get(), rank, chunk.data()), "cannot set chunks");
  // A checksum per chunk: damaged rows are found when a resume reads the file back.
  h5::check_status(H5Pset_fletcher32(plist.get()), "cannot set checksums");
  h5::Handle dataset =
      h5::check(H5Dcreate2(loc, name.c_str(), h5::Type<T>::file(), space.get(),
                           H5P_DEFAULT, plist.get(), H5P_DEFAULT),
                "cannot create dataset " + name);
  h5::write_string_attribute(dataset.get(), "units", units);
  return dataset;
}

// Grows the dataset to row + 1 rows and writes `data` (one row) into the last one.
template <class T>
void write_row(hid_t dataset, const std::string& name, hsize_t row, const T* data) {
  h5::Dims dims = h5::dataset_dims(dataset, name);
  dims[0] = row + 1;
  h5::check_status(H5Dset_extent(dataset, dims.data()), "cannot extend dataset " + name);
  h5::Handle file_space = h5::check(H5Dget_space(dataset), "cannot select in " + name);
  h5::Dims start(dims.size(), 0), count = dims;
  start[0] = row;
  count[0] = 1;
  h5::check_status(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(),
                                       nullptr, count.data(), nullptr),
                   "cannot select a row of " + name);
  h5::Handle memory_space = h5::make_space(count);
  h5::check_status(H5Dwrite(dataset, h5::Type<T>::memory(), memory_space.get(),
                            file_space.get(), H5P_DEFAULT, data),
                   "cannot write a row of " + name);
}

// std::filesystem::copy_file reports a full disk as an I/O error; this says which.
void copy_file(const std::string& from, const std::string& to) {
  std::FILE* in = std::fopen(from.c_str(), "rb");
  std::FILE* out = in ? std::fopen(to.c_str(), "wb") : nullptr;
  int error = out ? 0 : errno;
  std::vector<char> buffer(1 << 16);
  std::size_t n = buffer.size();
  while (!error && n == buffer.size()) {
    n = std::fread(buffer.data(), 1, buffer.size(), in);
    if (std::fwrite(buffer.data(), 1, n, out) != n || std::ferror(in))
      error = errno ? errno : EIO;
  }
  if (out && std::fclose(out) != 0 && !error)
    error = errno;
  if (in)
    std::fclose(in);
  if (error)
    throw std::runtime_error("cannot copy it to " + to + ": " + std::strerror(error));
}

// Opens a dataset of an existing file and cuts it to its first keep_rows rows.
bool exists(hid_t file, const std::string& name) {
  return H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0;
}

h5::Handle open_truncated(hid_t file, const std::string& name, long keep_rows) {
  h5::Handle dataset = h5::open_dataset(file, name);
  h5::Dims dims = h5::dataset_dims(dataset.get(), name);
  if (dims.empty() || dims[0] < static_cast<hsize_t>(keep_rows))
    throw std::runtime_error(
        "dataset " + name + " has " + std::to_string(dims.empty() ? 0 : dims[0]) +
        " rows, fewer than the " + std::to_string(keep_rows) + " to keep");
  dims[0] = static_cast<hsize_t>(keep_rows);
  h5::check_status(H5Dset_extent(dataset.get(), dims.data()),
                   "cannot truncate dataset " + name);
  return dataset;
}

// The first `rows` rows of a dataset whose rows have shape `row` (the other datasets may
// hold one row more than /time when a run was killed inside append()).
template <class T>
std::vector<T> read_rows(hid_t file, const std::string& name, hsize_t rows,
                         const h5::Dims& row) {
  h5::Dims dims;
  std::vector<T> data = h5::read_any_shape<T>(file, name, dims);
  if (dims.empty() || dims[0] < rows || h5::Dims(dims.begin() + 1, dims.end()) != row)
    throw std::runtime_error("dataset " + name + " has shape " + h5::shape_string(dims) +
                             ", expected " + std::to_string(rows) + " rows of " +
                             h5::shape_string(row));
  data.resize(rows * h5::element_count(row));
  return data;
}

} // namespace

struct TimeseriesWriter::Impl {
  std::string path, tmp; // the committed file and the copy being written
  int num_capsules = 0;
  long rows = 0;
  bool committed = false;
  h5::Handle file; // declared first, so closed after the datasets
  h5::Handle time, step;
  std::vector<h5::Handle> columns; // parallel to capsule_columns()

  ~Impl();
  void create();
  void reopen(long keep_rows);
  void close();
};

// Only an uncommitted copy is left: close it and remove it, so that `path` stays the
// file of record.
TimeseriesWriter::Impl::~Impl() {
  if (committed || tmp.empty())
    return;
  columns.clear();
  time.reset();
  step.reset();
  file.reset();
  std::remove(tmp.c_str());
}

void TimeseriesWriter::Impl::create() {
  file = h5::create_file(tmp);
  h5::write_attribute<std::int32_t>(file.get(), "num_capsules", num_capsules);
  time = create_extendible<double>(file.get(), "/time", {}, "gammadot t");
  step = create_extendible<std::int64_t>(file.get(), "/step", {}, "1");
  h5::Handle group =
      h5::check(H5Gcreate2(file.get(), "/capsule", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                "cannot create group /capsule");
  for (const CapsuleColumn& column : capsule_columns())
    columns.push_back(create_extendible<double>(
        file.get(), column_path(column), row_shape(column, num_capsules), column.units));
}

void TimeseriesWriter::Impl::reopen(long keep_rows) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw std::runtime_error("the file does not exist");
  copy_file(path, tmp);
  file = h5::open_file(tmp, H5F_ACC_RDWR);
  const int stored = h5::read_attribute<std::int32_t>(file.get(), "num_capsules");
  if (stored != num_capsules)
    throw std::runtime_error("it holds " + std::to_string(stored) +
                             " capsules, the run has " + std::to_string(num_capsules));
  time = open_truncated(file.get(), "/time", keep_rows);
  step = open_truncated(file.get(), "/step", keep_rows);
  for (const CapsuleColumn& column : capsule_columns()) {
    if (column.added_later && !exists(file.get(), column_path(column))) {
      const h5::Dims row = row_shape(column, num_capsules);
      columns.push_back(
          create_extendible<double>(file.get(), column_path(column), row, column.units));
      h5::Dims dims{static_cast<hsize_t>(keep_rows)}; // filled with zeros
      dims.insert(dims.end(), row.begin(), row.end());
      h5::check_status(H5Dset_extent(columns.back().get(), dims.data()),
                       "cannot extend dataset " + column_path(column));
      continue;
    }
    columns.push_back(open_truncated(file.get(), column_path(column), keep_rows));
  }
  rows = keep_rows;
}

// Datasets first: the file is written out when its last object closes.
void TimeseriesWriter::Impl::close() {
  for (std::size_t k = 0; k < columns.size(); ++k)
    columns[k].close("dataset " + column_path(capsule_columns()[k]));
  time.close("/time");
  step.close("/step");
  file.close("the file");
}

TimeseriesWriter::TimeseriesWriter(const std::string& path, int num_capsules,
                                   long keep_rows)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->num_capsules = num_capsules;
  const std::string action = keep_rows >= 0 ? "cannot update timeseries " + path +
                                                  " at row " + std::to_string(keep_rows)
                                            : "cannot create timeseries " + path;
  if (num_capsules < 1)
    throw std::runtime_error(action + ": num_capsules must be >= 1, got " +
                             std::to_string(num_capsules));
  impl_->tmp = path + ".tmp";
  try {
    if (keep_rows >= 0)
      impl_->reopen(keep_rows);
    else
      impl_->create();
  } catch (const std::exception& e) { // also bad_alloc from a damaged file
    impl_.reset();                    // removes the copy
    throw std::runtime_error(action + ": " + e.what());
  }
}

TimeseriesWriter::~TimeseriesWriter() = default;

void TimeseriesWriter::append(const Sample& sample) {
  Impl& s = *impl_;
  if (static_cast<int>(sample.capsules.size()) != s.num_capsules)
    throw std::runtime_error("timeseries " + s.path + ": sample has " +
                             std::to_string(sample.capsules.size()) +
                             " capsules, the file " + std::to_string(s.num_capsules));
  const hsize_t row = static_cast<hsize_t>(s.rows);
  try {
    const auto& columns = capsule_columns();
    std::vector<double> values;
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const hsize_t width = h5::element_count(columns[k].shape);
      values.resize(width * s.num_capsules);
      for (int c = 0; c < s.num_capsules; ++c)
        columns[k].get(sample.capsules[c], values.data() + c * width);
      write_row(s.columns[k].get(), column_path(columns[k]), row, values.data());
    }
    write_row(s.step.get(), "/step", row, &sample.step);
    // /time goes last: a row counts as written once /time holds it.
    write_row(s.time.get(), "/time", row, &sample.time);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("cannot append to timeseries " + s.path + " (in " + s.tmp +
                             "): " + e.what());
  }
  ++s.rows;
}

void TimeseriesWriter::commit() {
  Impl& s = *impl_;
  kill_point(KillPoint::series_written);
  try {
    s.close();
  } catch (const std::runtime_error& e) {
    std::remove(s.tmp.c_str());
    throw std::runtime_error("cannot write timeseries " + s.path + " (in " + s.tmp +
                             "): " + e.what());
  }
  // rename() replaces `path` in one step: readers see the old or the new file.
  if (std::rename(s.tmp.c_str(), s.path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(s.tmp.c_str());
    throw std::runtime_error("cannot write timeseries " + s.path + ": renaming " + s.tmp +
                             " failed: " + reason);
  }
  s.committed = true;
  kill_point(KillPoint::series_renamed);
}

long TimeseriesWriter::rows() const {
  return impl_->rows;
}

// Reads the header of every object in the file, so that a damaged header (its checksum)
// is found even where the rows are not (units attributes, for instance).
static void visit_every_header(hid_t file) {
  auto nothing = [](hid_t, const char*, const H5O_info_t*, void*) -> herr_t { return 0; };
  h5::check_status(
      H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_NATIVE, nothing, nullptr, H5O_INFO_ALL),
      "cannot read every object header");
}

std::vector<Sample> read_timeseries(const std::string& path) {
  return h5::read_or_explain("timeseries", path, [&] {
    h5::Handle file = h5::open_file(path, H5F_ACC_RDONLY);
    visit_every_header(file.get());
    const int m = h5::read_attribute<std::int32_t>(file.get(), "num_capsules");
    if (m < 1)
      throw std::runtime_error("num_capsules is " + std::to_string(m));
    h5::Dims dims;
    const std::vector<double> time =
        h5::read_any_shape<double>(file.get(), "/time", dims);
    if (dims.size() != 1)
      throw std::runtime_error("dataset /time is not one-dimensional");
    const hsize_t n = dims[0];
    const auto step = read_rows<std::int64_t>(file.get(), "/step", n, {});
    std::vector<Sample> samples(n);
    for (hsize_t i = 0; i < n; ++i) {
      samples[i].time = time[i];
      samples[i].step = step[i];
      samples[i].capsules.resize(m);
    }
    for (const CapsuleColumn& column : capsule_columns()) {
      if (column.added_later && !exists(file.get(), column_path(column)))
        continue; // an older file: the field keeps its zero
      const auto values =
          read_rows<double>(file.get(), column_path(column), n, row_shape(column, m));
      const hsize_t width = h5::element_count(column.shape);
      for (hsize_t i = 0; i < n; ++i)
        for (int c = 0; c < m; ++c)
          column.set(samples[i].capsules[c], values.data() + (i * m + c) * width);
    }
    return samples;
  });
}

} // namespace capsim
