#include "run/run_files.hpp"

#include "io/json_writer.hpp"
#include "io/timeseries_file.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace capsim {

void RunFiles::prepare_fresh(const std::string& dir) {
  if (fs::exists(dir + "/checkpoint.h5") || fs::exists(dir + "/summary.json"))
    throw ConfigError("output folder '" + dir +
                      "' already holds a run: continue it with `capsim run --resume " +
                      dir + "`, or choose another folder with -o");
  std::error_code ec;
  fs::create_directories(dir, ec);
  std::string probe = dir + "/.capsim_write_test";
  std::ofstream out(probe);
  if (ec || !out)
    throw ConfigError("output folder '" + dir + "' cannot be created or written" +
                      (ec ? ": " + ec.message() : ""));
  out.close();
  fs::remove(probe);
}

void RunFiles::copy_series(const std::string& from, const std::string& dir) {
  std::error_code ec;
  fs::copy_file(from + "/timeseries.h5", dir + "/timeseries.h5",
                fs::copy_options::overwrite_existing, ec);
  if (ec)
    throw std::runtime_error("cannot copy " + from + "/timeseries.h5 into " + dir + ": " +
                             ec.message());
}

void RunFiles::start(const RunOptions& o) const {
  write_text_atomically(dir_ + "/run.yaml", to_yaml(o));
  TimeseriesWriter(series_path(), num_capsules_).commit(); // an empty file
}

// Reading every row back finds a truncated file, broken structure and, through the
// chunks' checksums, damaged values.
void RunFiles::check_series(const Checkpoint& c) const {
  const std::string path = series_path();
  try {
    const long rows = long(read_timeseries(path).size());
    if (rows < c.samples_written)
      throw std::runtime_error("timeseries " + path + " holds " + std::to_string(rows) +
                               " rows, the checkpoint needs " +
                               std::to_string(c.samples_written));
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(
        std::string(e.what()) +
        ". Nothing was changed; the run cannot continue without the rows before its "
        "checkpoint: restore timeseries.h5 from a copy, or start the run again in a "
        "new folder");
  }
}

void RunFiles::resume(const Checkpoint& c, const RunOptions& o) {
  rows_written_ = c.samples_written;
  checkpoint_time_ = c.time;
  TimeseriesWriter(series_path(), num_capsules_, rows_written_).commit();
  snapshots_ = list_snapshots(dir_, c.snapshots_written);
  write_text_atomically(dir_ + "/run.yaml", to_yaml(o));
}

void RunFiles::flush_samples() {
  {
    TimeseriesWriter series(series_path(), num_capsules_, rows_written_);
    for (const auto& s : pending_)
      series.append(s);
    series.commit();
  }
  rows_written_ += long(pending_.size());
  pending_.clear();
}

void RunFiles::save_checkpoint(Checkpoint& c) {
  flush_samples();
  c.samples_written = rows_written_;
  c.snapshots_written = long(snapshots_.size());
  write_checkpoint(dir_ + "/checkpoint.h5", c);
  checkpoint_time_ = c.time;
}

void RunFiles::save_snapshot(const SnapshotFrame& frame,
                             const std::vector<std::array<int, 3>>& triangles,
                             const std::vector<Vec3>& positions) {
  write_snapshot(dir_, long(snapshots_.size()), frame, triangles, num_capsules_,
                 positions, snapshots_);
}

std::string RunFiles::resume_hint() const {
  if (checkpoint_time_ < 0)
    return ". No checkpoint was written yet: free space (or make the folder writable), "
           "then start the run again with the same command";
  char t[32];
  std::snprintf(t, sizeof t, "%.6g", checkpoint_time_);
  return ". The last good checkpoint (gammadot*t = " + std::string(t) + ") is kept in " +
         dir_ + "/checkpoint.h5: free space (or make the folder writable), then " +
         "continue with `capsim run --resume " + dir_ + "`";
}

std::vector<Sample> RunFiles::read_series() const {
  return read_timeseries(series_path());
}

} // namespace capsim
