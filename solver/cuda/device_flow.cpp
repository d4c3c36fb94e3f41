#include "cuda/device_flow.hpp"

#include "cuda/device_buffer.hpp"
#include "cuda/device_fft.hpp"
#include "cuda/device_kernels.hpp"

namespace capsim {

using cuda::DeviceArray;

struct DeviceFlow::Impl {
  // The mesh (one topology for all capsules) and its reference state.
  DeviceArray<int> triangles, corner_offset, corner;
  DeviceArray<ElementReference> refs;
  // The bending hinges (none without bending) and each node's hinge corners.
  DeviceArray<int> hinges, hinge_offset, hinge_corner;
  DeviceArray<HingeReference> hinge_refs;
  cuda::MeshView mesh;
  double gs = 0, kb = 0, shear_rate = 0;
  bool wrinkling = false; // the relaxed membrane energy (membrane.wrinkling)
  // Accurate quadrature: options plus the Gauss-Legendre rule of the polar integrals.
  DeviceArray<double> gl_x, gl_w;
  NearRule rule;
  // Work arrays: positions, velocities, traction, sources.
  DeviceArray<Vec3> x, u0, q, corner_grad, hinge_grad, y, f;
  DeviceArray<Vec3> repulsion_grad; // the host's repulsion gradient, where it is on
  DeviceArray<double> area;
  DeviceArray<TriangleLoad> loads;
  DeviceArray<cuda::TriangleBounds> bounds;
  // The real-space sums' bins (cell_bins.hpp): sources and triangle centroids.
  DeviceArray<int> bin_key, src_order, src_start, tri_order, tri_start;
  DeviceArray<Vec3> bin_scratch, y_binned, f_binned, centroid, centroid_binned;
  // The periodic box and Spectral Ewald (grid of 3 components, their spectra, plans).
  PeriodicBox box;
  SpreadGrid spread;
  DeviceArray<double> grid, spectrum;
  std::unique_ptr<cuda::DeviceFft3> fft;

  void upload_mesh(const Membrane& membrane, int num_capsules);
  void upload_hinges(const Membrane& membrane);
  void compute_traction(const Vec3* xd, const Vec3* repulsion);
  void compute_velocity(const Vec3* xd, const Vec3* repulsion, double t, Vec3* ud);
  void add_reciprocal(const ShearedLattice& g, const Vec3* xd, Vec3* ud);
  void add_real_space(const ShearedLattice& g, const Vec3* xd, Vec3* ud);
};

namespace {

// Each node's corners: its places in `nodes`, the nodes of each element in turn (corner k
// of element e at n e + k for elements of n nodes), as offsets into one list, in element
// order: the order in which the CPU adds each node's gradients.
struct NodeCorners {
  std::vector<int> offset, corners;
};
NodeCorners node_corners(const std::vector<int>& nodes, int num_nodes) {
  NodeCorners c{std::vector<int>(num_nodes + 1, 0), std::vector<int>(nodes.size())};
  for (int n : nodes)
    ++c.offset[n + 1];
  for (int a = 0; a < num_nodes; ++a)
    c.offset[a + 1] += c.offset[a];
  std::vector<int> fill(c.offset.begin(), c.offset.end() - 1);
  for (size_t j = 0; j < nodes.size(); ++j)
    c.corners[fill[nodes[j]]++] = int(j);
  return c;
}

} // namespace

void DeviceFlow::Impl::upload_mesh(const Membrane& membrane, int num_capsules) {
  const Topology& topo = membrane.topology();
  const int nt = int(topo.triangles.size()), nn = topo.num_nodes;
  std::vector<int> tri(3 * nt);
  for (int e = 0; e < nt; ++e)
    for (int k = 0; k < 3; ++k)
      tri[3 * e + k] = topo.triangles[e][k];
  const NodeCorners c = node_corners(tri, nn);
  triangles.upload(tri);
  corner_offset.upload(c.offset);
  corner.upload(c.corners);
  refs.upload(membrane.references());
  mesh.triangles = triangles.data();
  mesh.refs = refs.data();
  mesh.node_corner_offset = corner_offset.data();
  mesh.node_corner = corner.data();
  mesh.tri_per_capsule = nt;
  mesh.nodes_per_capsule = nn;
  mesh.capsules = num_capsules;
  upload_hinges(membrane);
}

void DeviceFlow::Impl::upload_hinges(const Membrane& membrane) {
  const std::vector<Hinge>& hs = membrane.hinges();
  if (hs.empty())
    return;
  std::vector<int> nodes;
  for (const Hinge& h : hs)
    nodes.insert(nodes.end(), {h.a, h.b, h.c, h.d});
  const NodeCorners c = node_corners(nodes, membrane.topology().num_nodes);
  hinges.upload(nodes);
  hinge_offset.upload(c.offset);
  hinge_corner.upload(c.corners);
  hinge_refs.upload(membrane.hinge_references());
  mesh.hinges = hinges.data();
  mesh.hinge_refs = hinge_refs.data();
  mesh.node_hinge_offset = hinge_offset.data();
  mesh.node_hinge = hinge_corner.data();
  mesh.hinges_per_capsule = int(hs.size());
}

DeviceFlow::DeviceFlow(const FlowSetup& setup)
    : Flow(setup), impl_(std::make_unique<Impl>()) {
  const Membrane& membrane = setup.membrane;
  const QuadratureOptions& quadrature = setup.quadrature;
  const PeriodicBox& box = setup.box;
  Impl& s = *impl_;
  s.upload_mesh(membrane, setup.num_capsules);
  s.gs = membrane.shear_modulus();
  s.kb = membrane.bending_modulus();
  s.wrinkling = membrane.wrinkling();
  s.shear_rate = setup.shear_rate;
  const LineRule gl = gauss_legendre_01(quadrature.singular_points);
  s.gl_x.upload(gl.x);
  s.gl_w.upload(gl.w);
  s.rule.far_ratio = quadrature.far_ratio;
  s.rule.near_ratio = quadrature.near_ratio;
  s.rule.max_depth = quadrature.max_depth;
  s.rule.gl_x = s.gl_x.data();
  s.rule.gl_w = s.gl_w.data();
  s.rule.gl_n = int(gl.x.size());
  const size_t n = size_t(s.mesh.num_nodes()), nt = size_t(s.mesh.num_triangles());
  for (auto* a : {&s.x, &s.u0, &s.q})
    a->resize(n);
  for (auto* a : {&s.corner_grad, &s.y, &s.f, &s.y_binned, &s.f_binned, &s.bin_scratch})
    a->resize(3 * nt);
  s.hinge_grad.resize(4 * size_t(s.mesh.num_hinges()));
  s.bin_key.resize(3 * nt);
  s.src_order.resize(3 * nt);
  s.tri_order.resize(nt);
  s.centroid.resize(nt);
  s.centroid_binned.resize(nt);
  s.area.resize(nt);
  s.loads.resize(nt);
  s.bounds.resize(nt);
  s.box = box;
  if (box.L > 0) {
    s.spread = make_spread_grid(box.L, box.grid.grid, box.grid.support, box.ewald.xi,
                                box.grid.eta);
    s.grid.resize(3 * grid_points(s.spread));
    s.spectrum.resize(3 * 2 * spectrum_modes(s.spread));
    s.fft = std::make_unique<cuda::DeviceFft3>(box.grid.grid);
  }
}

DeviceFlow::~DeviceFlow() = default;

void DeviceFlow::Impl::compute_traction(const Vec3* xd, const Vec3* repulsion) {
  cuda::element_forces(mesh, gs, wrinkling, xd, corner_grad.data(), area.data());
  const bool bending = mesh.num_hinges() > 0;
  if (bending)
    cuda::hinge_forces(mesh, kb, xd, hinge_grad.data());
  cuda::gather_nodes(mesh, corner_grad.data(), area.data(),
                     bending ? hinge_grad.data() : nullptr, repulsion, true, q.data());
}

// The same sequence as the CPU's spectral_ewald.cpp: spread, forward FFT, multiplier
// (with 8 pi / M^3: the 8 pi / V of eq. 2.3 times V / M^3, M^3 the grid points),
// backward FFT, gather.
void DeviceFlow::Impl::add_reciprocal(const ShearedLattice& g, const Vec3* xd, Vec3* ud) {
  const double n_real = double(grid_points(spread));
  grid.zero();
  cuda::spread(spread, g, int(y.size()), y.data(), f.data(), grid.data());
  fft->forward(grid.data(), spectrum.data());
  cuda::scale_spectrum(g, spread, box.ewald.xi, 8.0 * kPi / n_real, spectrum.data());
  fft->backward(spectrum.data(), grid.data());
  cuda::gather(spread, g, mesh.num_nodes(), xd, grid.data(), g.L * g.L * g.L / n_real,
               ud);
}

// The screened far sum and the near corrections through bins of width r_cut and of the
// near distance (cell lists: O(N) work); in boxes too small for the 5 x 3 x 3 stencil,
// the all-pairs kernels.
void DeviceFlow::Impl::add_real_space(const ShearedLattice& g, const Vec3* xd, Vec3* ud) {
  const int n = mesh.num_nodes(), m = int(y.size()), nt = mesh.num_triangles();
  const int src_bins = bins_per_side(g.L, box.ewald.r_cut);
  if (bins_usable(src_bins)) {
    src_start.resize(size_t(src_bins) * src_bins * src_bins + 1);
    cuda::bin_points(g, src_bins, m, y.data(), bin_key.data(), src_order.data(),
                     bin_scratch.data(), y_binned.data(), src_start.data());
    cuda::gather_by_order(m, src_order.data(), f.data(), f_binned.data());
    cuda::binned_screened_sum({g, src_bins, src_start.data()}, box.ewald.xi,
                              box.ewald.r_cut, n, xd, y_binned.data(), f_binned.data(),
                              ud);
  } else {
    cuda::screened_far_sum(g, box.ewald.xi, box.ewald.r_cut, n, xd, m, y.data(), f.data(),
                           ud);
  }
  const double near = rule.far_ratio * cuda::max_diameter(nt, bounds.data());
  const int tri_bins = bins_per_side(g.L, near);
  if (bins_usable(tri_bins)) {
    tri_start.resize(size_t(tri_bins) * tri_bins * tri_bins + 1);
    cuda::centroids_of(nt, bounds.data(), centroid.data());
    cuda::bin_points(g, tri_bins, nt, centroid.data(), bin_key.data(), tri_order.data(),
                     bin_scratch.data(), centroid_binned.data(), tri_start.data());
    cuda::binned_near_corrections({g, tri_bins, tri_start.data()}, mesh, xd,
                                  tri_order.data(), centroid_binned.data(), loads.data(),
                                  rule, ud);
  } else {
    cuda::periodic_near_corrections(g, mesh, xd, loads.data(), rule, ud);
  }
}

void DeviceFlow::Impl::compute_velocity(const Vec3* xd, const Vec3* repulsion, double t,
                                        Vec3* ud) {
  compute_traction(xd, repulsion);
  cuda::triangle_sources(mesh, xd, q.data(), loads.data(), bounds.data(), y.data(),
                         f.data());
  const int n = mesh.num_nodes(), m = int(y.size());
  if (box.L > 0) {
    const ShearedLattice g = make_sheared_lattice(box.L, shear_rate * t);
    add_real_space(g, xd, ud);
    add_reciprocal(g, xd, ud);
  } else {
    cuda::free_far_sum(n, xd, m, y.data(), f.data(), ud);
    cuda::free_near_corrections(mesh, xd, loads.data(), bounds.data(), rule, ud);
  }
  cuda::finish_velocity(n, xd, shear_rate, ud);
}

// The repulsion's gradient is the CPU's own (dynamics/repulsion.hpp), computed on the
// host: its pair search visits only the nodes near another capsule's bounding sphere,
// a few per cent of the work of an evaluation, and the device adds it where the CPU does,
// so both backends load the membrane with the same bits. Null where it is off.
const Vec3* DeviceFlow::repulsion_gradient(const std::vector<Vec3>& x, double t) const {
  if (!setup().repulsion.on() || !periodic())
    return nullptr;
  std::vector<Vec3> grad(x.size());
  add_repulsion(x, t, grad);
  impl_->repulsion_grad.upload(grad);
  return impl_->repulsion_grad.data();
}

void DeviceFlow::traction(const std::vector<Vec3>& x, double t,
                          std::vector<Vec3>& q) const {
  const Vec3* repulsion = repulsion_gradient(x, t);
  impl_->x.upload(x);
  impl_->compute_traction(impl_->x.data(), repulsion);
  impl_->q.download(q);
}

void DeviceFlow::evaluate_velocity(const std::vector<Vec3>& x, double t,
                                   std::vector<Vec3>& u) const {
  const Vec3* repulsion = repulsion_gradient(x, t);
  impl_->x.upload(x);
  impl_->compute_velocity(impl_->x.data(), repulsion, t, impl_->u0.data());
  impl_->u0.download(u);
}

} // namespace capsim
