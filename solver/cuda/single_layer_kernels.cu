// Single-layer sums on the device: the dense far sums over 3-point-rule sources (free
// space and screened real space) and the near-field corrections, around
// stokes/kernels/stokeslet.hpp, ewald_kernel.hpp and near_corrections.hpp.
#include "cuda/device_kernels.hpp"
#include "cuda/launch.cuh"
#include "stokes/cells/binned_sums.hpp"
#include "stokes/kernels/ewald_kernel.hpp"

namespace capsim::cuda {
namespace {

// One thread per target, a plain loop over every source. The threads of a warp read the
// same source together, a broadcast that the L1 and L2 caches serve, so staging sources
// in shared memory would save little (docs/gpu.md); and a kernel without shared memory
// and barriers runs unchanged in the host emulation, which cannot honour a barrier.
template <class Pair>
__device__ Vec3 source_sum(Vec3 xi, int m, const Vec3* y, const Vec3* f, Pair pair) {
  Vec3 sum;
  for (int k = 0; k < m; ++k)
    sum += pair(xi - y[k], f[k]);
  return sum;
}

__global__ void free_far_sum_kernel(int n, const Vec3* x, int m, const Vec3* y,
                                    const Vec3* f, Vec3* u) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n)
    u[i] =
        source_sum(x[i], m, y, f, [](Vec3 r, Vec3 q) { return stokeslet_apply(r, q); });
}

__global__ void screened_far_sum_kernel(ShearedLattice g, double xi_ewald, double r_cut,
                                        int n, const Vec3* x, int m, const Vec3* y,
                                        const Vec3* f, Vec3* u) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n)
    return;
  const double rc2 = r_cut * r_cut;
  u[i] = source_sum(x[i], m, y, f, [&](Vec3 r, Vec3 q) {
    r = wrap_to_cell(g, r);
    return dot(r, r) < rc2 ? ewald_real_apply(r, q, xi_ewald) : Vec3{};
  });
}

// x_i's vertex index (0-2) in global triangle e, or -1.
__device__ int vertex_of(const MeshView& mesh, int i, int e) {
  if (i / mesh.nodes_per_capsule != e / mesh.tri_per_capsule)
    return -1;
  const int a = i % mesh.nodes_per_capsule, t = e % mesh.tri_per_capsule;
  for (int k = 0; k < 3; ++k)
    if (mesh.triangles[3 * t + k] == a)
      return k;
  return -1;
}

// Every triangle is tested against every node (a cheap distance check); only the few
// near ones run the accurate rules.
__global__ void free_near_kernel(MeshView mesh, const Vec3* x, const TriangleLoad* loads,
                                 const TriangleBounds* bounds, NearRule rule, Vec3* u) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= mesh.num_nodes())
    return;
  const Vec3 xi = x[i];
  Vec3 sum;
  for (int e = 0; e < mesh.num_triangles(); ++e)
    if (norm(xi - bounds[e].centroid) < rule.far_ratio * bounds[e].diameter)
      sum += free_near_correction(xi, vertex_of(mesh, i, e), loads[e], rule);
  u[i] += sum;
}

__global__ void periodic_near_kernel(ShearedLattice g, MeshView mesh, const Vec3* x,
                                     const TriangleLoad* loads, NearRule rule, Vec3* u) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= mesh.num_nodes())
    return;
  const Vec3 xi = x[i];
  Vec3 sum;
  for (int e = 0; e < mesh.num_triangles(); ++e)
    sum += nearest_image_near_correction(g, xi, vertex_of(mesh, i, e), loads[e], rule);
  u[i] += sum;
}

__global__ void binned_screened_kernel(CellBins b, double xi, double r_cut, int n,
                                       const Vec3* x, const Vec3* ys, const Vec3* fs,
                                       Vec3* u) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n)
    u[i] = binned_screened_sum(b, ys, fs, xi, r_cut, x[i]);
}

__global__ void binned_near_kernel(CellBins b, MeshView mesh, const Vec3* x,
                                   const int* tri, const Vec3* wc,
                                   const TriangleLoad* loads, NearRule rule, Vec3* u) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= mesh.num_nodes())
    return;
  u[i] += binned_near_corrections(b, tri, wc, loads, rule, x[i],
                                  [&](int e) { return vertex_of(mesh, i, e); });
}

} // namespace

void binned_screened_sum(const CellBins& b, double xi, double r_cut, int n, const Vec3* x,
                         const Vec3* ys, const Vec3* fs, Vec3* u) {
  CAPSIM_LAUNCH(binned_screened_kernel, blocks_for(n), kBlock)
  (b, xi, r_cut, n, x, ys, fs, u);
  check_launch("binned_screened_sum");
}

void binned_near_corrections(const CellBins& b, const MeshView& mesh, const Vec3* x,
                             const int* tri, const Vec3* wc, const TriangleLoad* loads,
                             NearRule rule, Vec3* u) {
  CAPSIM_LAUNCH(binned_near_kernel, blocks_for(mesh.num_nodes()), kBlock)
  (b, mesh, x, tri, wc, loads, rule, u);
  check_launch("binned_near_corrections");
}

void free_far_sum(int n, const Vec3* x, int m, const Vec3* y, const Vec3* f, Vec3* u) {
  CAPSIM_LAUNCH(free_far_sum_kernel, blocks_for(n), kBlock)(n, x, m, y, f, u);
  check_launch("free_far_sum");
}

void free_near_corrections(const MeshView& mesh, const Vec3* x, const TriangleLoad* loads,
                           const TriangleBounds* bounds, NearRule rule, Vec3* u) {
  CAPSIM_LAUNCH(free_near_kernel, blocks_for(mesh.num_nodes()), kBlock)
  (mesh, x, loads, bounds, rule, u);
  check_launch("free_near_corrections");
}

void screened_far_sum(const ShearedLattice& g, double xi, double r_cut, int n,
                      const Vec3* x, int m, const Vec3* y, const Vec3* f, Vec3* u) {
  CAPSIM_LAUNCH(screened_far_sum_kernel, blocks_for(n), kBlock)
  (g, xi, r_cut, n, x, m, y, f, u);
  check_launch("screened_far_sum");
}

void periodic_near_corrections(const ShearedLattice& g, const MeshView& mesh,
                               const Vec3* x, const TriangleLoad* loads, NearRule rule,
                               Vec3* u) {
  CAPSIM_LAUNCH(periodic_near_kernel, blocks_for(mesh.num_nodes()), kBlock)
  (g, mesh, x, loads, rule, u);
  check_launch("periodic_near_corrections");
}

} // namespace capsim::cuda
