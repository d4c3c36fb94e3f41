#pragma once
// checkpoint.h5, written atomically: the data go to `path.tmp`, which is closed and then
// renamed over `path`, so a run killed at any moment leaves the last good checkpoint.
#include "io/records.hpp"

#include <string>

namespace capsim {

void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);

// Throws std::runtime_error naming the path and what is wrong (missing, not HDF5,
// a dataset missing or of the wrong size) for a corrupt or foreign file.
Checkpoint read_checkpoint(const std::string& path);

} // namespace capsim
