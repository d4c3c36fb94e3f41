#pragma once
// Mesh snapshots that ParaView opens: snapshots/snapshot_NNNNNN.h5 holds /nodes (N, 3)
// and /triangles (T, 3) int32 for all capsules together (capsule c's nodes start at
// c * nodes_per_capsule), and snapshots.xdmf is a temporal collection over all of them,
// rewritten (write-then-rename) after each new snapshot.
#include "common/vec3.hpp"

#include <array>
#include <string>
#include <vector>

namespace capsim {

struct SnapshotIndexEntry {
  std::string h5_name; // file name relative to the run directory
  double time;
  long num_nodes;
  long num_triangles;
};

// Writes snapshot number `index` into `run_dir` and rewrites run_dir/snapshots.xdmf to
// list entries[0..index]. `entries` is the caller's list; the new entry is appended.
void write_snapshot(const std::string& run_dir, long index, double time,
                    const std::vector<std::array<int, 3>>& triangles, int num_capsules,
                    const std::vector<Vec3>& positions,
                    std::vector<SnapshotIndexEntry>& entries);

// Rebuilds the entry list from the snapshot files present (used on resume), keeping
// only indices < count.
std::vector<SnapshotIndexEntry> list_snapshots(const std::string& run_dir, long count);

} // namespace capsim
