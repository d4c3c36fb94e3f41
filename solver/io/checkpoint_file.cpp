#include "io/checkpoint_file.hpp"

#include "io/hdf5_util.hpp"
#include "io/kill_point.hpp"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace capsim {
namespace {

void check_consistent(const Checkpoint& c) {
  const std::size_t nodes =
      static_cast<std::size_t>(c.num_capsules) * c.nodes_per_capsule;
  if (c.num_capsules < 1 || c.nodes_per_capsule < 0)
    throw std::runtime_error("num_capsules " + std::to_string(c.num_capsules) +
                             " or nodes_per_capsule " +
                             std::to_string(c.nodes_per_capsule) + " is invalid");
  if (c.volume0.size() != static_cast<std::size_t>(c.num_capsules))
    throw std::runtime_error("volume0 has " + std::to_string(c.volume0.size()) +
                             " entries for " + std::to_string(c.num_capsules) +
                             " capsules");
  if (c.positions.size() != nodes)
    throw std::runtime_error("positions has " + std::to_string(c.positions.size()) +
                             " nodes, num_capsules * nodes_per_capsule is " +
                             std::to_string(nodes));
  if (c.samples_written < 0 || c.snapshots_written < 0 || c.step < 0)
    throw std::runtime_error("step, samples_written or snapshots_written is negative");
}

// A NaN or Inf read back (a corrupt file, a state saved by a broken build) would reach
// the kernels at the first step and come out as NaN averages: refused here, naming the
// dataset, before anything is computed.
void check_finite(const Checkpoint& c) {
  auto fail = [](const std::string& dataset, double v, const std::string& where = "") {
    std::ostringstream m;
    m << dataset << where << " is ";
    if (std::isfinite(v))
      m << v << ", out of range";
    else
      m << "not finite (" << v << ")";
    throw std::runtime_error(m.str());
  };
  if (!(std::isfinite(c.time) && c.time >= 0))
    fail("/time", c.time);
  if (!(std::isfinite(c.next_dt) && c.next_dt >= 0))
    fail("/next_dt", c.next_dt);
  if (!(std::isfinite(c.sample_origin_time) && c.sample_origin_time >= 0))
    fail("/sample_origin_time", c.sample_origin_time);
  if (!(std::isfinite(c.step_origin_time) && c.step_origin_time >= 0))
    fail("/step_origin_time", c.step_origin_time);
  if (c.step_origin_index < 0 || c.step_origin_index > c.step)
    fail("/step_origin_index", double(c.step_origin_index));
  for (std::size_t i = 0; i < c.volume0.size(); ++i)
    if (!(std::isfinite(c.volume0[i]) && c.volume0[i] > 0))
      fail("/volume0", c.volume0[i], " of capsule " + std::to_string(i));
  for (std::size_t i = 0; i < c.positions.size(); ++i)
    for (double v : {c.positions[i].x, c.positions[i].y, c.positions[i].z})
      if (!std::isfinite(v))
        fail("/positions", v, " of node " + std::to_string(i));
}

void write_contents(const std::string& file_path, const Checkpoint& c) {
  h5::Handle file = h5::create_file(file_path);
  const hid_t f = file.get();
  h5::write_scalar<double>(f, "/time", c.time);
  h5::write_scalar<std::int64_t>(f, "/step", c.step);
  h5::write_scalar<std::int64_t>(f, "/samples_written", c.samples_written);
  h5::write_scalar<std::int64_t>(f, "/snapshots_written", c.snapshots_written);
  h5::write_scalar<std::int32_t>(f, "/num_capsules", c.num_capsules);
  h5::write_scalar<std::int32_t>(f, "/nodes_per_capsule", c.nodes_per_capsule);
  h5::write_scalar<double>(f, "/next_dt", c.next_dt);
  h5::write_scalar<std::int64_t>(f, "/rejected_steps", c.rejected_steps);
  // Only where it is not (0, 0), so that every other checkpoint stays as it was.
  if (c.sample_origin_time != 0 || c.sample_origin_index != 0) {
    h5::write_scalar<double>(f, "/sample_origin_time", c.sample_origin_time);
    h5::write_scalar<std::int64_t>(f, "/sample_origin_index", c.sample_origin_index);
  }
  if (c.step_origin_time != 0 || c.step_origin_index != 0) {
    h5::write_scalar<double>(f, "/step_origin_time", c.step_origin_time);
    h5::write_scalar<std::int64_t>(f, "/step_origin_index", c.step_origin_index);
  }
  h5::write_dataset(f, "/volume0", {c.volume0.size()}, c.volume0.data());
  std::vector<double> xyz;
  xyz.reserve(3 * c.positions.size());
  for (const Vec3& p : c.positions)
    xyz.insert(xyz.end(), {p.x, p.y, p.z});
  h5::write_dataset(f, "/positions", {c.positions.size(), 3}, xyz.data());
  h5::write_string_dataset(f, "/options_yaml", c.options_yaml);
  kill_point(KillPoint::checkpoint_written);
  // Only a successful close means the data reached the file; a failed one must not be
  // renamed over the last good checkpoint.
  file.close("the file");
}

} // namespace

void write_checkpoint(const std::string& path, const Checkpoint& checkpoint) {
  const std::string tmp = path + ".tmp";
  try {
    check_consistent(checkpoint);
    write_contents(tmp, checkpoint);
  } catch (const std::runtime_error& e) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write checkpoint " + path + ": " + e.what());
  }
  kill_point(KillPoint::checkpoint_closed);
  // rename() replaces `path` in one step: a reader sees the old or the new file, never
  // a partly written one.
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write checkpoint " + path + ": renaming " + tmp +
                             " failed: " + reason);
  }
}

Checkpoint read_checkpoint(const std::string& path) {
  return h5::read_or_explain("checkpoint", path, [&] {
    h5::Handle file = h5::open_file(path, H5F_ACC_RDONLY);
    const hid_t f = file.get();
    Checkpoint c;
    c.time = h5::read_scalar<double>(f, "/time");
    c.step = h5::read_scalar<std::int64_t>(f, "/step");
    c.samples_written = h5::read_scalar<std::int64_t>(f, "/samples_written");
    c.snapshots_written = h5::read_scalar<std::int64_t>(f, "/snapshots_written");
    c.num_capsules = h5::read_scalar<std::int32_t>(f, "/num_capsules");
    c.nodes_per_capsule = h5::read_scalar<std::int32_t>(f, "/nodes_per_capsule");
    // Absent in checkpoints of fixed-step versions, which never needed them.
    if (H5Lexists(f, "/next_dt", H5P_DEFAULT) > 0) {
      c.next_dt = h5::read_scalar<double>(f, "/next_dt");
      c.rejected_steps = h5::read_scalar<std::int64_t>(f, "/rejected_steps");
    }
    if (H5Lexists(f, "/sample_origin_time", H5P_DEFAULT) > 0) {
      c.sample_origin_time = h5::read_scalar<double>(f, "/sample_origin_time");
      c.sample_origin_index = h5::read_scalar<std::int64_t>(f, "/sample_origin_index");
    }
    if (H5Lexists(f, "/step_origin_time", H5P_DEFAULT) > 0) {
      c.step_origin_time = h5::read_scalar<double>(f, "/step_origin_time");
      c.step_origin_index = h5::read_scalar<std::int64_t>(f, "/step_origin_index");
    }
    if (c.num_capsules < 1 || c.nodes_per_capsule < 0)
      throw std::runtime_error("num_capsules " + std::to_string(c.num_capsules) +
                               " or nodes_per_capsule " +
                               std::to_string(c.nodes_per_capsule) + " is invalid");
    const hsize_t nodes = static_cast<hsize_t>(c.num_capsules) * c.nodes_per_capsule;
    c.volume0 = h5::read_dataset<double>(f, "/volume0", {hsize_t(c.num_capsules)});
    const auto xyz = h5::read_dataset<double>(f, "/positions", {nodes, 3});
    c.positions.resize(nodes);
    for (hsize_t i = 0; i < nodes; ++i)
      c.positions[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
    c.options_yaml = h5::read_string_dataset(f, "/options_yaml");
    check_finite(c);
    return c;
  });
}

} // namespace capsim
