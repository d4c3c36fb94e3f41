#pragma once
// Mesh snapshots that ParaView opens: snapshots/snapshot_NNNNNN.h5 holds /nodes (N, 3)
// and /triangles (T, 3) int32 for all capsules together (capsule c's nodes start at
// c * nodes_per_capsule), with the scalars /time, /num_capsules, /box_side (L; 0 in the
// dilute limit) and /strain (the Lees-Edwards offset of the lattice), and the fields to
// colour by: per node /capsule (int32), /velocity and /traction (N, 3), /tension_max and
// /tension_min (N); per element /area_dilatation, /element_tension_max and
// /element_tension_min (T). snapshots.xdmf is a temporal collection over all of them,
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
  bool fields = false;           // has the fields (snapshots of older versions do not)
  bool element_tensions = false; // has the per-element tensions (added later)
};

// Writes snapshot number `index` into `run_dir` and rewrites run_dir/snapshots.xdmf to
// list entries[0..index]. `entries` is the caller's list; the new entry is appended.
struct SnapshotFrame {
  double time = 0;
  double box_side = 0; // L of the periodic box, 0 for unbounded flow
  double strain = 0;   // lattice strain offset s in [-1/2, 1/2)
  // Fields, all present or all empty: per node (all capsules) and per element.
  std::vector<Vec3> velocity, traction;         // mu gammadot units
  std::vector<double> tension_max, tension_min; // principal tensions over Gs
  std::vector<double> area_dilatation;          // deformed over reference area
  std::vector<double> element_tension_max,      // T1 and T2 of each element, over Gs
      element_tension_min;
};

void write_snapshot(const std::string& run_dir, long index, const SnapshotFrame& frame,
                    const std::vector<std::array<int, 3>>& triangles, int num_capsules,
                    const std::vector<Vec3>& positions,
                    std::vector<SnapshotIndexEntry>& entries);

// Rebuilds the entry list from the snapshot files present (used on resume), keeping
// only indices < count.
std::vector<SnapshotIndexEntry> list_snapshots(const std::string& run_dir, long count);

} // namespace capsim
