#pragma once
// timeseries.h5: one row per sample, extendible datasets (HDF5 C API).
//   /time            (n)          gammadot t          /step (n) int64
//   /capsule/D, /capsule/theta_D_deg, /capsule/principal_diff, /capsule/theta_S_deg,
//   /capsule/energy, /capsule/volume_error        (n, M)
//   /capsule/stresslet (n, M, 3, 3)   /capsule/centroid (n, M, 3)
// Each dataset carries a "units" attribute.
#include "io/records.hpp"

#include <memory>
#include <string>
#include <vector>

namespace capsim {

class TimeseriesWriter {
public:
  // Creates `path`, or, when keep_rows >= 0, reopens it and truncates every dataset to
  // its first keep_rows rows (resume from a checkpoint). Throws std::runtime_error with
  // the path in the message on failure.
  TimeseriesWriter(const std::string& path, int num_capsules, long keep_rows = -1);
  ~TimeseriesWriter();
  TimeseriesWriter(const TimeseriesWriter&) = delete;
  TimeseriesWriter& operator=(const TimeseriesWriter&) = delete;

  void append(const Sample& sample);
  void flush(); // H5Fflush: rows appended so far are on disk
  long rows() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Reads every row back (for the summary and for tests).
std::vector<Sample> read_timeseries(const std::string& path);

} // namespace capsim
