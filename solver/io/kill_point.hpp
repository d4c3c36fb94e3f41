#pragma once
// A testing aid for the kill-and-resume soak (docs/reliability.md): with the environment
// variable CAPSIM_TEST_KILL_AT=<point>:<k>, capsim raises SIGKILL on itself the k-th time
// it passes <point>, so a test can stop it inside a write window that a kill at a random
// moment rarely hits. Without the variable a point costs one comparison; it is read
// once, and the points sit only on the output path (once per checkpoint).
namespace capsim {

enum class KillPoint {
  series_written,     // rows appended to timeseries.h5.tmp, the file still open
  series_renamed,     // timeseries.h5 replaced, the checkpoint not yet written
  checkpoint_written, // checkpoint.h5.tmp filled, the file still open
  checkpoint_closed,  // checkpoint.h5.tmp closed, not yet renamed over checkpoint.h5
};

// Throws std::runtime_error when the variable names no known point or a bad k.
void kill_point(KillPoint point);

} // namespace capsim
