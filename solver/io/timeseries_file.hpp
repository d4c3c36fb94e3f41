#pragma once
// timeseries.h5: one row per sample, extendible datasets (HDF5 C API).
//   /time            (n)          gammadot t          /step (n) int64
//   /capsule/D, /capsule/theta_D_deg, /capsule/principal_diff, /capsule/theta_S_deg,
//   /capsule/energy, /capsule/volume_error, /capsule/volume_drift,
//   /capsule/repelled_nodes, /capsule/compressed_elements, /capsule/min_tension  (n, M)
//   /capsule/stresslet (n, M, 3, 3)   /capsule/centroid (n, M, 3)
// Each dataset carries a "units" attribute.
#include "io/records.hpp"

#include <memory>
#include <string>
#include <vector>

namespace capsim {

// Writes go to a copy, `path`.tmp, which commit() closes and renames over `path`: a run
// killed, or a disk that fills up, while rows are written leaves the last committed file
// as it was. Each commit copies the file once (a few MB for a long suspension run).
class TimeseriesWriter {
public:
  // A new, empty file, or, when keep_rows >= 0, a copy of `path` with every dataset cut
  // to its first keep_rows rows (resume from a checkpoint). Throws std::runtime_error
  // with the path in the message on failure.
  TimeseriesWriter(const std::string& path, int num_capsules, long keep_rows = -1);
  // Without commit() (an error), removes the copy; `path` is unchanged.
  ~TimeseriesWriter();
  TimeseriesWriter(const TimeseriesWriter&) = delete;
  TimeseriesWriter& operator=(const TimeseriesWriter&) = delete;

  void append(const Sample& sample);
  void commit(); // closes the copy, checking that it reached the disk, and renames it
  long rows() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Reads every row back (for the summary and for tests).
std::vector<Sample> read_timeseries(const std::string& path);

} // namespace capsim
