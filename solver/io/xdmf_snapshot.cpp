#include "io/xdmf_snapshot.hpp"

#include "io/hdf5_util.hpp"
#include "io/json_writer.hpp"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace capsim {
namespace {

namespace fs = std::filesystem;

// Relative to the run directory, which is also where snapshots.xdmf lives: ParaView
// resolves the HDF5 paths in an XDMF file relative to the XDMF file itself.
std::string snapshot_name(long index) {
  char name[64];
  std::snprintf(name, sizeof name, "snapshots/snapshot_%06ld.h5", index);
  return name;
}

// Triangles of all capsules as one (T, 3) table, capsule c's indices shifted by
// c * nodes_per_capsule.
std::vector<std::int32_t> all_triangles(const std::vector<std::array<int, 3>>& triangles,
                                        int num_capsules, int nodes_per_capsule) {
  std::vector<std::int32_t> out;
  out.reserve(3 * triangles.size() * num_capsules);
  for (int c = 0; c < num_capsules; ++c)
    for (const auto& t : triangles)
      for (int node : t) {
        if (node < 0 || node >= nodes_per_capsule)
          throw std::runtime_error("triangle node index " + std::to_string(node) +
                                   " outside [0, " + std::to_string(nodes_per_capsule) +
                                   ")");
        out.push_back(c * nodes_per_capsule + node);
      }
  return out;
}

bool has_fields(const SnapshotFrame& f, size_t nodes, size_t elements) {
  const bool any = !f.velocity.empty() || !f.traction.empty() || !f.tension_max.empty() ||
                   !f.tension_min.empty() || !f.area_dilatation.empty() ||
                   !f.element_tension_max.empty() || !f.element_tension_min.empty();
  if (any &&
      (f.velocity.size() != nodes || f.traction.size() != nodes ||
       f.tension_max.size() != nodes || f.tension_min.size() != nodes ||
       f.area_dilatation.size() != elements || f.element_tension_max.size() != elements ||
       f.element_tension_min.size() != elements))
    throw std::runtime_error("snapshot fields do not match the mesh");
  return any;
}

void write_scalars(hid_t file, const std::string& name, const std::vector<double>& v) {
  h5::write_dataset(file, name, {v.size()}, v.data());
}

void write_vectors(hid_t file, const std::string& name, const std::vector<Vec3>& v) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three doubles");
  h5::write_dataset(file, name, {v.size(), 3}, reinterpret_cast<const double*>(v.data()));
}

void write_fields(hid_t file, const SnapshotFrame& frame, int nodes_per_capsule) {
  std::vector<std::int32_t> capsule(frame.velocity.size());
  for (size_t i = 0; i < capsule.size(); ++i)
    capsule[i] = std::int32_t(i / nodes_per_capsule);
  h5::write_dataset(file, "/capsule", {capsule.size()}, capsule.data());
  write_vectors(file, "/velocity", frame.velocity);
  write_vectors(file, "/traction", frame.traction);
  write_scalars(file, "/tension_max", frame.tension_max);
  write_scalars(file, "/tension_min", frame.tension_min);
  write_scalars(file, "/area_dilatation", frame.area_dilatation);
  write_scalars(file, "/element_tension_max", frame.element_tension_max);
  write_scalars(file, "/element_tension_min", frame.element_tension_min);
}

void write_snapshot_file(const std::string& path, const SnapshotFrame& frame,
                         int num_capsules, const std::vector<Vec3>& positions,
                         const std::vector<std::int32_t>& triangles, bool fields) {
  h5::Handle file = h5::create_file(path);
  h5::write_scalar<double>(file.get(), "/time", frame.time);
  h5::write_scalar<double>(file.get(), "/box_side", frame.box_side);
  h5::write_scalar<double>(file.get(), "/strain", frame.strain);
  h5::write_scalar<int>(file.get(), "/num_capsules", num_capsules);
  write_vectors(file.get(), "/nodes", positions);
  h5::write_dataset(file.get(), "/triangles", {triangles.size() / 3, 3},
                    triangles.data());
  if (fields)
    write_fields(file.get(), frame, int(positions.size() / num_capsules));
  file.close("the file");
}

// One XDMF attribute: `dims` "N" (scalar) or "N 3" (vector), centred on nodes or cells.
std::string attribute_xml(const SnapshotIndexEntry& e, const std::string& name,
                          bool vector, bool cell, bool integer = false) {
  const std::string n = std::to_string(cell ? e.num_triangles : e.num_nodes);
  return "        <Attribute Name=\"" + name + "\" AttributeType=\"" +
         (vector ? "Vector" : "Scalar") + "\" Center=\"" + (cell ? "Cell" : "Node") +
         "\">\n          <DataItem Dimensions=\"" + n + (vector ? " 3" : "") +
         "\" NumberType=\"" +
         (integer ? "Int\" Precision=\"4" : "Float\" Precision=\"8") +
         "\" Format=\"HDF\">" + e.h5_name + ":/" + name +
         "</DataItem>\n        </Attribute>\n";
}

std::string attributes_xml(const SnapshotIndexEntry& e) {
  if (!e.fields)
    return "";
  return attribute_xml(e, "capsule", false, false, true) +
         attribute_xml(e, "velocity", true, false) +
         attribute_xml(e, "traction", true, false) +
         attribute_xml(e, "tension_max", false, false) +
         attribute_xml(e, "tension_min", false, false) +
         attribute_xml(e, "area_dilatation", false, true) +
         (e.element_tensions ? attribute_xml(e, "element_tension_max", false, true) +
                                   attribute_xml(e, "element_tension_min", false, true)
                             : "");
}

std::string grid_xml(const SnapshotIndexEntry& e) {
  const std::string t = std::to_string(e.num_triangles);
  const std::string n = std::to_string(e.num_nodes);
  return "      <Grid Name=\"" + fs::path(e.h5_name).stem().string() +
         "\" GridType=\"Uniform\">\n"
         "        <Time Value=\"" +
         json_number(e.time) +
         "\"/>\n"
         "        <Topology TopologyType=\"Triangle\" NumberOfElements=\"" +
         t +
         "\">\n"
         "          <DataItem Dimensions=\"" +
         t + " 3\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" + e.h5_name +
         ":/triangles</DataItem>\n"
         "        </Topology>\n"
         "        <Geometry GeometryType=\"XYZ\">\n"
         "          <DataItem Dimensions=\"" +
         n + " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" + e.h5_name +
         ":/nodes</DataItem>\n"
         "        </Geometry>\n" +
         attributes_xml(e) + "      </Grid>\n";
}

std::string xdmf_text(const std::vector<SnapshotIndexEntry>& entries) {
  std::string text = "<?xml version=\"1.0\" ?>\n"
                     "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
                     "<Xdmf Version=\"3.0\">\n"
                     "  <Domain>\n"
                     "    <Grid Name=\"capsules\" GridType=\"Collection\" "
                     "CollectionType=\"Temporal\">\n";
  for (const SnapshotIndexEntry& e : entries)
    text += grid_xml(e);
  return text + "    </Grid>\n"
                "  </Domain>\n"
                "</Xdmf>\n";
}

} // namespace

void write_snapshot(const std::string& run_dir, long index, const SnapshotFrame& frame,
                    const std::vector<std::array<int, 3>>& triangles, int num_capsules,
                    const std::vector<Vec3>& positions,
                    std::vector<SnapshotIndexEntry>& entries) {
  const std::string name = snapshot_name(index);
  const std::string path = (fs::path(run_dir) / name).string();
  bool fields = false;
  try {
    if (num_capsules < 1 || positions.size() % num_capsules != 0)
      throw std::runtime_error(std::to_string(positions.size()) +
                               " positions do not split into " +
                               std::to_string(num_capsules) + " capsules");
    const int nodes_per_capsule = static_cast<int>(positions.size() / num_capsules);
    const auto all = all_triangles(triangles, num_capsules, nodes_per_capsule);
    fields = has_fields(frame, positions.size(), all.size() / 3);
    fs::create_directories(fs::path(path).parent_path());
    write_snapshot_file(path, frame, num_capsules, positions, all, fields);
  } catch (const std::exception& e) { // also filesystem_error from create_directories
    throw std::runtime_error("cannot write snapshot " + path + ": " + e.what());
  }
  // Entries are kept in index order; any beyond `index` are stale (e.g. from before a
  // resume) and are dropped, so the index lists exactly snapshots 0..index.
  if (entries.size() > static_cast<std::size_t>(index))
    entries.resize(index);
  const long num_triangles = static_cast<long>(triangles.size()) * num_capsules;
  entries.push_back({name, frame.time, static_cast<long>(positions.size()), num_triangles,
                     fields, fields});
  write_text_atomically((fs::path(run_dir) / "snapshots.xdmf").string(),
                        xdmf_text(entries));
}

std::vector<SnapshotIndexEntry> list_snapshots(const std::string& run_dir, long count) {
  std::vector<SnapshotIndexEntry> entries;
  for (long index = 0; index < count; ++index) {
    const std::string name = snapshot_name(index);
    const std::string path = (fs::path(run_dir) / name).string();
    std::error_code ec;
    if (!fs::exists(path, ec))
      continue; // only the snapshots present are listed
    entries.push_back(h5::read_or_explain("snapshot", path, [&] {
      h5::Handle file = h5::open_file(path, H5F_ACC_RDONLY);
      h5::Handle n = h5::open_dataset(file.get(), "/nodes");
      h5::Handle t = h5::open_dataset(file.get(), "/triangles");
      const h5::Dims nodes = h5::dataset_dims(n.get(), "/nodes");
      const h5::Dims triangles = h5::dataset_dims(t.get(), "/triangles");
      if (nodes.size() != 2 || triangles.size() != 2)
        throw std::runtime_error("/nodes or /triangles is not a table");
      const double time = h5::read_scalar<double>(file.get(), "/time");
      const bool fields = H5Lexists(file.get(), "/velocity", H5P_DEFAULT) > 0;
      const bool tensions =
          H5Lexists(file.get(), "/element_tension_max", H5P_DEFAULT) > 0;
      return SnapshotIndexEntry{
          name,   time,    static_cast<long>(nodes[0]), static_cast<long>(triangles[0]),
          fields, tensions};
    }));
  }
  return entries;
}

} // namespace capsim
