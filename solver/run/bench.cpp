#include "run/bench.hpp"

#include "common/suspension.hpp"
#include "config/run_options.hpp"
#include "dynamics/packing.hpp"
#include "io/json_writer.hpp"
#include "membrane/membrane_forces.hpp"
#include "run/flow_factory.hpp"
#include "run/run_plan.hpp"
#include "stokes/ewald/ewald_setup.hpp"
#include "stokes/ewald/real_space_sum.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <cmath>
#include <fstream>
#include <omp.h>
#include <random>
#include <sstream>

namespace capsim {
namespace {

constexpr double kStretch = 1.1;        // each capsule stretched along a random axis
constexpr double kReferenceTol = 1e-10; // the reference: direct Ewald at this tolerance

struct Configuration {
  Icosphere mesh;
  double L = 0;
  std::vector<Vec3> x, q;
};

// The ranges of the options, in the messages of the run keys ("--phi: must be a number
// in (0, 0.45], got 0.5"); NaN fails every range.
void check_options(const BenchOptions& o) {
  require_in("--capsules", o.capsules, {1, 100000}, true);
  require_in("--mesh-level", o.mesh_level, {0, 5}, true);
  require_in("--phi", o.phi, {0, 0.45, true, false});
  require_in("--patch-level", o.ewald.patch_level, {0, double(o.mesh_level)}, true);
  require_in("--tolerance", o.ewald.tolerance, {1e-12, 1, false, true});
  require_in("--strain", o.strain, {-1e6, 1e6});
  require_in("--seed", o.seed, {0, 2147483647.0}, true);
  if (o.ewald.xi != 0) // 0: automatic
    require_in("--xi", o.ewald.xi, {0, 100, true, false});
  require_in("--repeats", o.repeats, {1, 100}, true);
}

// M capsules packed at random (seeded) at volume fraction phi, each an ellipsoid
// stretched by kStretch along a random axis, loaded by its neo-Hookean membrane
// traction at Ca = 1 (the traction scale drops out of relative errors).
Configuration make_configuration(const BenchOptions& o) {
  Configuration c;
  c.mesh = make_icosphere(o.mesh_level);
  c.L = periodic_box_side(o.capsules, o.phi);
  PackingOptions pack;
  pack.capsules = o.capsules;
  pack.box = c.L;
  pack.min_gap = 2.0 * (kStretch - 1.0) + 0.05;
  pack.seed = unsigned(o.seed);
  std::vector<Vec3> centres;
  try {
    centres = pack_spheres(pack);
  } catch (const std::runtime_error& e) {
    throw ConfigError(std::string("--phi: ") + e.what());
  }
  Membrane membrane(c.mesh.topology, c.mesh.positions.data(), 1.0);
  std::mt19937 rng(unsigned(o.seed) + 7919u);
  std::normal_distribution<double> normal;
  std::vector<Vec3> grad, qc;
  for (const Vec3& centre : centres) {
    Vec3 n{normal(rng), normal(rng), normal(rng)};
    n = (1.0 / norm(n)) * n;
    std::vector<Vec3> xc;
    for (const Vec3& p : c.mesh.positions) {
      const double along = dot(p, n);
      xc.push_back(centre + (kStretch * along) * n +
                   (1.0 / std::sqrt(kStretch)) * (p - along * n));
    }
    membrane.energy_gradient(xc.data(), grad);
    membrane.nodal_load(xc.data(), grad, LoadMapping::lumped, qc);
    c.x.insert(c.x.end(), xc.begin(), xc.end());
    c.q.insert(c.q.end(), qc.begin(), qc.end());
  }
  return c;
}

std::string reference_header(const BenchOptions& o, size_t n) {
  std::ostringstream h;
  h.precision(17);
  h << "capsim-bench-reference v1 capsules " << o.capsules << " level " << o.mesh_level
    << " phi " << o.phi << " seed " << o.seed << " strain " << o.strain << " nodes " << n
    << " tolerance " << kReferenceTol << "\n";
  return h.str();
}

bool read_reference(const std::string& file, const std::string& header,
                    std::vector<Vec3>& u) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  if (!in || !std::getline(in, line) || line + "\n" != header)
    return false;
  in.read(reinterpret_cast<char*>(u.data()), std::streamsize(u.size() * sizeof(Vec3)));
  return bool(in);
}

void write_reference(const std::string& file, const std::string& header,
                     const std::vector<Vec3>& u) {
  const std::string tmp = file + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << header;
    out.write(reinterpret_cast<const char*>(u.data()),
              std::streamsize(u.size() * sizeof(Vec3)));
    if (!out)
      throw std::runtime_error("cannot write the reference file " + tmp);
  }
  std::rename(tmp.c_str(), file.c_str());
}

// The direct-Ewald reference at kReferenceTol, read from the cache file when it matches.
std::vector<Vec3> reference_velocity(const BenchOptions& o, const Configuration& c,
                                     const QuadratureOptions& quad, double& seconds) {
  std::vector<Vec3> u(c.x.size());
  const std::string header = reference_header(o, c.x.size());
  seconds = 0;
  if (!o.reference_file.empty() && read_reference(o.reference_file, header, u))
    return u;
  const long points = far_rule_points(c.mesh.topology, o.capsules);
  const PeriodicBox box = make_periodic_box(c.L, {EwaldMethod::direct, kReferenceTol},
                                            long(c.x.size()), points);
  const double t0 = omp_get_wtime();
  periodic_single_layer_velocity(c.mesh.topology, o.capsules, c.x, c.q,
                                 make_sheared_lattice(c.L, o.strain), box.ewald, quad, u);
  seconds = omp_get_wtime() - t0;
  if (!o.reference_file.empty())
    write_reference(o.reference_file, header, u);
  return u;
}

} // namespace

std::string run_benchmark(const BenchOptions& o) {
  check_options(o);
  const Configuration c = make_configuration(o);
  const QuadratureOptions quad;
  const long nodes = long(c.x.size());
  const long points = far_rule_points(c.mesh.topology, o.capsules);
  // The box as a run on the cpu backend gets it, from the same resolution.
  const PeriodicBox box = plan_periodic_box(c.L, o.ewald, capabilities_of(Backend::cpu),
                                            nodes, points, "--xi");
  const ShearedLattice lattice = make_sheared_lattice(c.L, o.strain);
  std::unique_ptr<SpectralEwald> spectral;
  if (box.method == EwaldMethod::spectral)
    spectral = std::make_unique<SpectralEwald>(c.L, box.ewald, box.grid);
  std::vector<Vec3> u;
  if (spectral) // warm-up: FFTW's first execution and the grid's first touch
    periodic_single_layer_velocity(c.mesh.topology, o.capsules, c.x, c.q, lattice,
                                   box.ewald, quad, u,
                                   reciprocal_sum(box, spectral.get()));
  PeriodicTimings t;
  const double t0 = omp_get_wtime();
  for (int r = 0; r < o.repeats; ++r)
    periodic_single_layer_velocity(c.mesh.topology, o.capsules, c.x, c.q, lattice,
                                   box.ewald, quad, u,
                                   reciprocal_sum(box, spectral.get()), &t);
  const double per_eval = (omp_get_wtime() - t0) / o.repeats;

  JsonWriter j;
  j.begin_object();
  j.field("method", to_string(o.ewald.method));
  j.field("capsules", o.capsules);
  j.field("mesh_level", o.mesh_level);
  j.field("phi", o.phi);
  j.field("box", c.L);
  j.field("strain", o.strain);
  j.field("seed", o.seed);
  j.field("tolerance", o.ewald.tolerance);
  j.field("threads", omp_get_max_threads());
  j.field("nodes", nodes);
  j.field("sources", points);
  j.field("xi", box.ewald.xi);
  j.field("r_cut", box.ewald.r_cut);
  j.field("k_cut", box.ewald.k_cut);
  if (box.method == EwaldMethod::patches)
    j.field("patches", long(o.capsules) * icosphere_triangles(box.patch_level));
  if (box.method == EwaldMethod::spectral) {
    j.field("grid", std::vector<double>(box.grid.grid, box.grid.grid + 3));
    j.field("support", box.grid.support);
    j.field("precision", box.grid.single ? "single" : "double");
  }
  j.field("real_space_precision", box.ewald.single_real ? "single" : "double");
  j.field("repeats", o.repeats);
  j.field("seconds_per_eval", per_eval);
  j.begin_object("seconds");
  j.field("setup", t.setup / o.repeats);
  j.field("near", t.near / o.repeats);
  j.field("real_space", t.real_space / o.repeats);
  j.field("reciprocal", t.reciprocal / o.repeats);
  if (box.method == EwaldMethod::spectral) {
    j.field("spreading", t.spectral.spread / o.repeats);
    j.field("fft", t.spectral.fft / o.repeats);
    j.field("gathering", t.spectral.gather / o.repeats);
  }
  j.end_object();
  const double pairs = double(t.real_space_pairs) / o.repeats;
  j.field("real_space_pairs", pairs);
  j.field("real_space_gflops",
          pairs * kScreenedPairFlops / (t.real_space / o.repeats) / 1e9);
  if (o.reference) {
    double ref_seconds = 0;
    const std::vector<Vec3> ref = reference_velocity(o, c, quad, ref_seconds);
    double diff2 = 0, ref2 = 0, max_diff = 0, max_ref = 0;
    for (size_t i = 0; i < ref.size(); ++i) {
      diff2 += dot(u[i] - ref[i], u[i] - ref[i]);
      ref2 += dot(ref[i], ref[i]);
      max_diff = std::max(max_diff, norm(u[i] - ref[i]));
      max_ref = std::max(max_ref, norm(ref[i]));
    }
    j.field("rel_error", std::sqrt(diff2 / ref2));
    j.field("max_rel_error", max_diff / max_ref);
    j.begin_object("reference");
    j.field("method", "direct");
    j.field("tolerance", kReferenceTol);
    j.field("seconds", ref_seconds); // 0 when read from the cache file
    j.end_object();
  }
  j.end_object();
  return j.str();
}

} // namespace capsim
