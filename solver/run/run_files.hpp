#pragma once
// The files of one run folder as the time loop writes them (docs/usage.md): run.yaml, the
// time series, the checkpoint and the snapshots. Samples are held until the next
// checkpoint; then the time series is opened, appended and closed, and the checkpoint is
// renamed into place. Between checkpoints no file of the run is open for writing, so a
// run killed at any moment leaves readable files, and h5py can read them during a run.
#include "config/run_options.hpp"
#include "io/checkpoint_file.hpp"
#include "io/records.hpp"
#include "io/xdmf_snapshot.hpp"

#include <string>
#include <vector>

namespace capsim {

class RunFiles {
public:
  RunFiles(std::string dir, int num_capsules)
      : dir_(std::move(dir)), num_capsules_(num_capsules) {}

  // Refuses a folder that already holds a run; checks that the folder can be written.
  static void prepare_fresh(const std::string& dir);
  // A branch's time series: the one of the run in `from`, copied into `dir` (its rows
  // after the checkpoint are dropped as on a resume).
  static void copy_series(const std::string& from, const std::string& dir);
  // A fresh run: run.yaml and an empty time series.
  void start(const RunOptions& o) const;
  // Stops a resume before any file is changed when the time series is damaged or holds
  // fewer rows than the checkpoint needs.
  void check_series(const Checkpoint& c) const;
  // Continues from checkpoint c: drops the rows written after it (a run killed between
  // the two), lists its snapshots, and writes run.yaml with the options of this part.
  void resume(const Checkpoint& c, const RunOptions& o);

  void add_sample(Sample s) { pending_.push_back(std::move(s)); }
  // Samples written and pending: the index of the next one.
  long samples() const { return rows_written_ + long(pending_.size()); }
  // Appends the pending samples to the time series.
  void flush_samples();
  // Flushes the samples, then writes `c` with the counts of rows and snapshots filled in.
  void save_checkpoint(Checkpoint& c);
  void save_snapshot(const SnapshotFrame& frame,
                     const std::vector<std::array<int, 3>>& triangles,
                     const std::vector<Vec3>& positions);

  // gammadot t of the checkpoint on disk; < 0 before the first.
  double checkpoint_time() const { return checkpoint_time_; }
  // What to do after a failed write: where the run can continue from.
  std::string resume_hint() const;
  std::vector<Sample> read_series() const;
  const std::string& dir() const { return dir_; }

private:
  std::string series_path() const { return dir_ + "/timeseries.h5"; }

  std::string dir_;
  int num_capsules_;
  long rows_written_ = 0;
  double checkpoint_time_ = -1;
  std::vector<Sample> pending_; // samples taken since the last checkpoint
  std::vector<SnapshotIndexEntry> snapshots_;
};

} // namespace capsim
