#include "run/multipole_error.hpp"

#include "config/run_options.hpp"
#include "io/checkpoint_file.hpp"
#include "mesh/surface_geometry.hpp"
#include "stokes/ewald/multipole_patches.hpp"

#include <sstream>

namespace capsim {
namespace {

// P = 1 is one patch (level -1); P = 20 * 4^l is icosphere level l.
int patch_level_of(int patches, int mesh_level) {
  if (patches == 1)
    return -1;
  for (int l = 0; l <= mesh_level; ++l)
    if (patches == icosphere_triangles(l))
      return l;
  throw ConfigError("--patches: each must be 1 or 20 * 4^l with l <= mesh_level (" +
                    std::to_string(mesh_level) + "), got " + std::to_string(patches));
}

} // namespace

std::vector<MultipoleErrorRow> multipole_error(const std::string& run_dir,
                                               const std::vector<int>& patch_counts,
                                               const std::vector<double>& distances) {
  Checkpoint c = read_checkpoint(run_dir + "/checkpoint.h5");
  RunOptions o = parse_checkpoint_options(c.options_yaml, {}, "checkpoint in " + run_dir);
  Icosphere mesh = make_icosphere(o.mesh_level);
  if (c.nodes_per_capsule != mesh.topology.num_nodes)
    throw ConfigError("checkpoint in " + run_dir + " does not match its mesh_level");
  Membrane membrane(mesh.topology, mesh.positions.data(), 1.0 / o.ca);
  const Vec3* x = c.positions.data(); // the first capsule
  std::vector<Vec3> grad, q;
  membrane.energy_gradient(x, grad);
  membrane.nodal_load(x, grad, o.load, q);
  const Vec3 centre = volume_centroid(mesh.topology, x);
  const Vec3 dirs[3] = {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}}; // flow, vorticity, gradient
  std::vector<MultipoleErrorRow> rows;
  for (int p : patch_counts) {
    auto patches = patch_moments(mesh.topology, o.mesh_level,
                                 patch_level_of(p, o.mesh_level), x, q.data());
    for (double r : distances) {
      double e[3];
      for (int d = 0; d < 3; ++d) {
        Vec3 point = centre + r * dirs[d];
        Vec3 ref = surface_velocity_at(point, mesh.topology, x, q.data());
        e[d] = norm(patch_velocity(point, patches) - ref) / norm(ref);
      }
      rows.push_back(
          {o.ca, o.mesh_level, p, r, e[0], e[1], e[2], (e[0] + e[1] + e[2]) / 3.0});
    }
  }
  return rows;
}

std::string multipole_error_csv(const std::vector<MultipoleErrorRow>& rows) {
  std::ostringstream s;
  s.precision(8);
  s << "ca,mesh_level,patches,r_over_a,error_flow,error_vorticity,error_gradient,"
       "error_mean\n";
  for (const auto& r : rows)
    s << r.ca << "," << r.mesh_level << "," << r.patches << "," << r.r << ","
      << r.error_flow << "," << r.error_vorticity << "," << r.error_gradient << ","
      << r.error_mean << "\n";
  return s.str();
}

} // namespace capsim
