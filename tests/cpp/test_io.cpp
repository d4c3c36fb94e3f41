// Output and checkpoint files: round trips, resume truncation, atomic writes, and clear
// errors for missing or corrupt files.
#include "io/checkpoint_file.hpp"
#include "io/hdf5_util.hpp"
#include "io/json_writer.hpp"
#include "io/timeseries_file.hpp"
#include "io/xdmf_snapshot.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <signal.h>
#include <string>
#include <sys/resource.h>

namespace fs = std::filesystem;
using namespace capsim;
using Catch::Matchers::Contains;

namespace {

// A fresh directory under the system temp folder, removed when the test ends.
struct TempDir {
  fs::path path;
  TempDir() {
    std::random_device rd;
    path = fs::temp_directory_path() / ("capsim_test_io_" + std::to_string(rd()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

// Distinct values in every field, so that a swapped column or capsule shows up.
Sample make_sample(int row, int num_capsules, double offset = 0) {
  Sample s;
  s.time = 0.25 * row + offset;
  s.step = 10 * row + static_cast<long>(offset);
  for (int c = 0; c < num_capsules; ++c) {
    const double b = 100 * row + 10 * c + offset;
    CapsuleSample k;
    k.taylor_D = b + 0.1;
    k.theta_D_deg = b + 0.2;
    k.principal_diff = b + 0.3;
    k.theta_S_deg = b + 0.4;
    k.energy = b + 0.5;
    k.volume_error = b + 0.6;
    k.volume_drift = b + 0.65;
    k.repelled_nodes = b + 0.66;
    k.compressed_elements = b + 0.67;
    k.min_tension = -b - 0.68;
    k.centroid = {b + 0.7, b + 0.8, b + 0.9};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        k.stresslet.m[i][j] = b + 0.01 * (3 * i + j);
    s.capsules.push_back(k);
  }
  return s;
}

void require_equal(const Sample& a, const Sample& b) {
  REQUIRE(a.time == b.time);
  REQUIRE(a.step == b.step);
  REQUIRE(a.capsules.size() == b.capsules.size());
  for (std::size_t c = 0; c < a.capsules.size(); ++c) {
    const CapsuleSample& x = a.capsules[c];
    const CapsuleSample& y = b.capsules[c];
    REQUIRE(x.taylor_D == y.taylor_D);
    REQUIRE(x.theta_D_deg == y.theta_D_deg);
    REQUIRE(x.principal_diff == y.principal_diff);
    REQUIRE(x.theta_S_deg == y.theta_S_deg);
    REQUIRE(x.energy == y.energy);
    REQUIRE(x.volume_error == y.volume_error);
    REQUIRE(x.volume_drift == y.volume_drift);
    REQUIRE(x.repelled_nodes == y.repelled_nodes);
    REQUIRE(x.compressed_elements == y.compressed_elements);
    REQUIRE(x.min_tension == y.min_tension);
    REQUIRE(x.centroid.x == y.centroid.x);
    REQUIRE(x.centroid.y == y.centroid.y);
    REQUIRE(x.centroid.z == y.centroid.z);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        REQUIRE(x.stresslet.m[i][j] == y.stresslet.m[i][j]);
  }
}

Checkpoint make_checkpoint() {
  Checkpoint c;
  c.time = 12.5;
  c.step = 1234;
  c.samples_written = 56;
  c.snapshots_written = 7;
  c.num_capsules = 2;
  c.nodes_per_capsule = 3;
  c.volume0 = {4.18, 4.19};
  for (int i = 0; i < 6; ++i)
    c.positions.push_back({i + 0.1, i + 0.2, i + 0.3});
  c.options_yaml = "ca: 0.2\nname: \"run 1\"\n";
  return c;
}

} // namespace

TEST_CASE("io: timeseries round trip") {
  TempDir dir;
  const std::string path = dir.file("timeseries.h5");
  {
    TimeseriesWriter writer(path, 2);
    for (int row = 0; row < 5; ++row)
      writer.append(make_sample(row, 2));
    writer.commit();
    REQUIRE(writer.rows() == 5);
  }
  const std::vector<Sample> samples = read_timeseries(path);
  REQUIRE(samples.size() == 5);
  for (int row = 0; row < 5; ++row)
    require_equal(samples[row], make_sample(row, 2));

  h5::Handle file = h5::open_file(path, H5F_ACC_RDONLY);
  h5::Handle stresslet = h5::open_dataset(file.get(), "/capsule/stresslet");
  REQUIRE(h5::dataset_dims(stresslet.get(), "") == h5::Dims{5, 2, 3, 3});
  REQUIRE(h5::read_string_attribute(stresslet.get(), "units") == "Gs a^2");
  REQUIRE(h5::read_attribute<std::int32_t>(file.get(), "num_capsules") == 2);
}

TEST_CASE("io: timeseries reopened with keep_rows drops later rows") {
  TempDir dir;
  const std::string path = dir.file("timeseries.h5");
  {
    TimeseriesWriter writer(path, 2);
    for (int row = 0; row < 5; ++row)
      writer.append(make_sample(row, 2));
    writer.commit();
  }
  {
    TimeseriesWriter writer(path, 2, 3);
    REQUIRE(writer.rows() == 3);
    for (int row = 3; row < 5; ++row)
      writer.append(make_sample(row, 2, 0.5));
    writer.commit();
  }
  const std::vector<Sample> samples = read_timeseries(path);
  REQUIRE(samples.size() == 5);
  for (int row = 0; row < 3; ++row)
    require_equal(samples[row], make_sample(row, 2));
  for (int row = 3; row < 5; ++row)
    require_equal(samples[row], make_sample(row, 2, 0.5));

  REQUIRE_THROWS_WITH(TimeseriesWriter(path, 2, 6), Contains(path) && Contains("fewer"));
  REQUIRE_THROWS_WITH(TimeseriesWriter(path, 3, 2), Contains("capsules"));
  REQUIRE_THROWS_WITH(TimeseriesWriter(dir.file("none.h5"), 2, 0),
                      Contains("none.h5") && Contains("does not exist"));
}

TEST_CASE("io: a timeseries of an older version (no repelled_nodes, compressed_elements, "
          "min_tension) reads as zeros and resumes") {
  TempDir dir;
  const std::string path = dir.file("timeseries.h5");
  {
    TimeseriesWriter writer(path, 2);
    for (int row = 0; row < 4; ++row)
      writer.append(make_sample(row, 2));
    writer.commit();
  }
  {
    h5::Handle file = h5::open_file(path, H5F_ACC_RDWR);
    for (const char* name : {"/capsule/repelled_nodes", "/capsule/compressed_elements",
                             "/capsule/min_tension"})
      REQUIRE(H5Ldelete(file.get(), name, H5P_DEFAULT) >= 0);
  }
  std::vector<Sample> samples = read_timeseries(path);
  REQUIRE(samples.size() == 4);
  CHECK(samples[3].capsules[1].repelled_nodes == 0);
  CHECK(samples[3].capsules[1].compressed_elements == 0);
  CHECK(samples[3].capsules[1].min_tension == 0);
  CHECK(samples[3].capsules[1].taylor_D == make_sample(3, 2).capsules[1].taylor_D);
  {
    TimeseriesWriter writer(path, 2, 3); // resume at row 3: the column comes back
    writer.append(make_sample(3, 2, 0.5));
    writer.commit();
  }
  samples = read_timeseries(path);
  REQUIRE(samples.size() == 4);
  CHECK(samples[2].capsules[0].repelled_nodes == 0);
  CHECK(samples[2].capsules[0].min_tension == 0);
  require_equal(samples[3], make_sample(3, 2, 0.5));
}

TEST_CASE("io: checkpoint round trip") {
  TempDir dir;
  const std::string path = dir.file("checkpoint.h5");
  const Checkpoint c = make_checkpoint();
  write_checkpoint(path, c);
  const Checkpoint r = read_checkpoint(path);
  REQUIRE(r.time == c.time);
  REQUIRE(r.step == c.step);
  REQUIRE(r.samples_written == c.samples_written);
  REQUIRE(r.snapshots_written == c.snapshots_written);
  REQUIRE(r.num_capsules == c.num_capsules);
  REQUIRE(r.nodes_per_capsule == c.nodes_per_capsule);
  REQUIRE(r.volume0 == c.volume0);
  REQUIRE(r.positions.size() == c.positions.size());
  for (std::size_t i = 0; i < c.positions.size(); ++i) {
    REQUIRE(r.positions[i].x == c.positions[i].x);
    REQUIRE(r.positions[i].y == c.positions[i].y);
    REQUIRE(r.positions[i].z == c.positions[i].z);
  }
  REQUIRE(r.options_yaml == c.options_yaml);
}

TEST_CASE("io: checkpoint is replaced atomically and leaves no .tmp file") {
  TempDir dir;
  const std::string path = dir.file("checkpoint.h5");
  Checkpoint c = make_checkpoint();
  write_checkpoint(path, c);
  c.step = 2000;
  write_checkpoint(path, c);
  REQUIRE(read_checkpoint(path).step == 2000);
  REQUIRE_FALSE(fs::exists(path + ".tmp"));

  c.positions.pop_back(); // inconsistent: the old checkpoint must survive
  REQUIRE_THROWS_WITH(write_checkpoint(path, c), Contains(path) && Contains("positions"));
  REQUIRE(read_checkpoint(path).step == 2000);
  REQUIRE_FALSE(fs::exists(path + ".tmp"));
}

TEST_CASE("io: corrupt checkpoint throws naming the path") {
  TempDir dir;
  const std::string path = dir.file("checkpoint.h5");
  {
    std::ofstream out(path, std::ios::binary);
    std::mt19937 rng(1);
    for (int i = 0; i < 4096; ++i)
      out.put(static_cast<char>(rng() & 0xff));
  }
  REQUIRE_THROWS_WITH(read_checkpoint(path),
                      Contains(path) && Contains("not a capsim checkpoint"));

  // A valid HDF5 file with one dataset removed.
  write_checkpoint(path, make_checkpoint());
  {
    h5::Handle file = h5::open_file(path, H5F_ACC_RDWR);
    REQUIRE(H5Ldelete(file.get(), "/positions", H5P_DEFAULT) >= 0);
  }
  REQUIRE_THROWS_WITH(read_checkpoint(path),
                      Contains(path) && Contains("dataset /positions missing"));
}

namespace {

// Writes beyond `bytes` per file fail with EFBIG (as on a full disk) while it lives: the
// soft file size limit, with SIGXFSZ ignored so that write() returns the error.
struct FileSizeLimit {
  rlimit old{};
  void (*old_handler)(int);
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &old);
    old_handler = signal(SIGXFSZ, SIG_IGN);
    rlimit limited = old;
    limited.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limited);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, old_handler);
  }
};

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

} // namespace

TEST_CASE("io: a checkpoint or time series that cannot be written (disk full) leaves the "
          "last good file and no .tmp, and says why") {
  TempDir dir;
  const std::string checkpoint = dir.file("checkpoint.h5");
  Checkpoint c = make_checkpoint();
  write_checkpoint(checkpoint, c);
  c.positions.assign(20000, {1, 2, 3}); // 480 kB: beyond the limit below
  c.nodes_per_capsule = 10000;
  const std::string series = dir.file("timeseries.h5");
  {
    TimeseriesWriter writer(series, 2);
    writer.append(make_sample(0, 2));
    writer.commit();
  }
  const std::string series_before = bytes_of(series);
  {
    FileSizeLimit limit(fs::file_size(series) + 1000);
    CHECK_THROWS_WITH(write_checkpoint(checkpoint, c),
                      Contains(checkpoint) && Contains("File too large"));
    TimeseriesWriter writer(series, 2, 1);
    for (int row = 1; row < 200; ++row) // the second chunk of rows does not fit
      writer.append(make_sample(row, 2));
    CHECK_THROWS_WITH(writer.commit(), Contains(series) && Contains("File too large"));
  }
  CHECK(read_checkpoint(checkpoint).step == make_checkpoint().step);
  CHECK(bytes_of(series) == series_before);
  CHECK(read_timeseries(series).size() == 1);
  CHECK_FALSE(fs::exists(checkpoint + ".tmp"));
  CHECK_FALSE(fs::exists(series + ".tmp"));
}

TEST_CASE("io: missing checkpoint throws naming the path") {
  TempDir dir;
  const std::string path = dir.file("no_such_checkpoint.h5");
  REQUIRE_THROWS_WITH(read_checkpoint(path),
                      Contains(path) && Contains("does not exist"));
}

TEST_CASE("io: xdmf snapshots and their index") {
  TempDir dir;
  const std::string run_dir = dir.path.string();
  const std::vector<std::array<int, 3>> triangles = {{0, 1, 2}, {0, 2, 3}};
  std::vector<Vec3> positions;
  for (int i = 0; i < 8; ++i)
    positions.push_back({1.0 * i, 0, 0});
  std::vector<SnapshotIndexEntry> entries;
  SnapshotFrame plain;
  plain.box_side = 7.5;
  plain.strain = 0.25;
  write_snapshot(run_dir, 0, plain, triangles, 2, positions, entries);
  // The second with fields: per node (8) and per element (2 capsules x 2 triangles).
  SnapshotFrame frame = plain;
  frame.time = 0.5;
  frame.strain = 0.3;
  frame.velocity = frame.traction = positions;
  frame.tension_max.assign(8, 0.7);
  frame.tension_min.assign(8, -0.1);
  frame.area_dilatation = {1.0, 1.1, 1.2, 1.3};
  frame.element_tension_max = {0.5, 0.6, 0.7, 0.8};
  frame.element_tension_min = {-0.5, 0.0, 0.1, 0.2};
  write_snapshot(run_dir, 1, frame, triangles, 2, positions, entries);
  // Fields that do not match the mesh are refused, naming the file.
  SnapshotFrame short_fields = frame;
  short_fields.area_dilatation.pop_back();
  CHECK_THROWS_WITH(
      write_snapshot(run_dir, 2, short_fields, triangles, 2, positions, entries),
      Contains("snapshot_000002.h5") && Contains("do not match"));
  short_fields = frame;
  short_fields.element_tension_min.pop_back();
  CHECK_THROWS_WITH(
      write_snapshot(run_dir, 2, short_fields, triangles, 2, positions, entries),
      Contains("do not match"));

  REQUIRE(entries.size() == 2);
  REQUIRE(fs::exists(dir.path / "snapshots/snapshot_000000.h5"));
  REQUIRE(fs::exists(dir.path / "snapshots/snapshot_000001.h5"));
  REQUIRE_FALSE(fs::exists(dir.path / "snapshots.xdmf.tmp"));
  std::ifstream in(dir.path / "snapshots.xdmf");
  const std::string xdmf((std::istreambuf_iterator<char>(in)), {});
  CHECK_THAT(xdmf, Contains("CollectionType=\"Temporal\""));
  CHECK_THAT(xdmf, Contains("snapshots/snapshot_000000.h5:/nodes"));
  CHECK_THAT(xdmf, Contains("snapshots/snapshot_000001.h5:/triangles"));
  CHECK_THAT(xdmf, Contains("<Time Value=\"0.5\"/>"));

  // Capsule 1's triangles are shifted by its 4 nodes.
  h5::Handle file =
      h5::open_file(run_dir + "/snapshots/snapshot_000001.h5", H5F_ACC_RDONLY);
  const auto t = h5::read_dataset<std::int32_t>(file.get(), "/triangles", {4, 3});
  REQUIRE(t == std::vector<std::int32_t>{0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7});
  CHECK(h5::read_scalar<double>(file.get(), "/box_side") == 7.5);
  CHECK(h5::read_scalar<double>(file.get(), "/strain") == 0.3);
  CHECK(h5::read_scalar<int>(file.get(), "/num_capsules") == 2);
  CHECK(h5::read_dataset<std::int32_t>(file.get(), "/capsule", {8}) ==
        std::vector<std::int32_t>{0, 0, 0, 0, 1, 1, 1, 1});
  CHECK(h5::read_dataset<double>(file.get(), "/area_dilatation", {4}) ==
        frame.area_dilatation);
  CHECK(h5::read_dataset<double>(file.get(), "/element_tension_max", {4}) ==
        frame.element_tension_max);
  CHECK(h5::read_dataset<double>(file.get(), "/element_tension_min", {4}) ==
        frame.element_tension_min);
  CHECK(h5::read_dataset<double>(file.get(), "/velocity", {8, 3})[3 * 5] == 5.0);
  // Only the snapshot with fields lists them, as node and cell attributes.
  CHECK(xdmf.find("snapshot_000000.h5:/velocity") == std::string::npos);
  CHECK_THAT(xdmf, Contains("<Attribute Name=\"velocity\" AttributeType=\"Vector\" "
                            "Center=\"Node\">"));
  CHECK_THAT(xdmf, Contains("<Attribute Name=\"area_dilatation\" "
                            "AttributeType=\"Scalar\" Center=\"Cell\">"));
  CHECK_THAT(xdmf, Contains("snapshots/snapshot_000001.h5:/tension_min"));
  CHECK_THAT(xdmf, Contains("<Attribute Name=\"element_tension_min\" "
                            "AttributeType=\"Scalar\" Center=\"Cell\">"));
  CHECK_THAT(xdmf, Contains("snapshots/snapshot_000001.h5:/element_tension_max"));

  const auto listed = list_snapshots(run_dir, 1);
  REQUIRE(listed.size() == 1);
  REQUIRE(list_snapshots(run_dir, 5).size() == 2);
  const auto second = list_snapshots(run_dir, 2)[1];
  REQUIRE(second.h5_name == "snapshots/snapshot_000001.h5");
  REQUIRE(second.time == 0.5);
  REQUIRE(second.num_nodes == 8);
  REQUIRE(second.num_triangles == 4);
  CHECK(second.fields);
  CHECK(second.element_tensions);
  CHECK_FALSE(listed[0].fields);
  CHECK_FALSE(listed[0].element_tensions);
}

TEST_CASE("io: json writer escapes strings and writes null for non-finite numbers") {
  JsonWriter w;
  w.begin_object();
  w.field("name", std::string("say \"hi\"\nback\\slash"));
  w.field("nan", std::numeric_limits<double>::quiet_NaN());
  w.field("inf", -std::numeric_limits<double>::infinity());
  w.field("count", 3);
  w.field("ok", true);
  w.field("list", std::vector<double>{0.5, 2});
  Mat3 m;
  m.m[0][0] = 1;
  m.m[2][1] = -2.5;
  w.matrix("S", m);
  w.begin_array("rows");
  w.value(0.1);
  w.begin_object();
  w.end_object();
  w.end_array();
  w.end_object();
  const std::string expected = R"({
  "name": "say \"hi\"\nback\\slash",
  "nan": null,
  "inf": null,
  "count": 3,
  "ok": true,
  "list": [0.5, 2],
  "S": [[1, 0, 0], [0, 0, 0], [0, -2.5, 0]],
  "rows": [
    0.1,
    {}
  ]
}
)";
  REQUIRE(w.str() == expected);

  JsonWriter open;
  open.begin_object();
  REQUIRE_THROWS_AS(open.str(), std::logic_error);
  REQUIRE_THROWS_AS(open.value(1.0), std::logic_error); // no key
}

TEST_CASE("io: write_text_atomically replaces the file and leaves no .tmp") {
  TempDir dir;
  const std::string path = dir.file("summary.json");
  write_text_atomically(path, "first\n");
  write_text_atomically(path, "second\n");
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  REQUIRE(text == "second\n");
  REQUIRE_FALSE(fs::exists(path + ".tmp"));
  REQUIRE_THROWS_WITH(write_text_atomically(dir.file("no/such/dir/x.json"), "x"),
                      Contains("no/such/dir/x.json"));
}
