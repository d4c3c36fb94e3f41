// Single-layer sums on the device: the dense far sums over 3-point-rule sources (free
// space and screened real space) and the near-field corrections, around
// stokes/stokeslet.hpp, ewald_kernel.hpp and near_corrections.hpp.
#include "cuda/device_kernels.hpp"
#include "cuda/launch.cuh"
#include "stokes/binned_sums.hpp"
#include "stokes/ewald_kernel.hpp"

namespace capsim::cuda {
namespace {

// One thread per target; the block walks the sources in tiles staged in shared memory,
// so each source is read from global memory once per block rather than once per thread.
// Plain doubles there: a __shared__ array may not run Vec3's initialisers.
template <class Pair>
__device__ Vec3 tiled_source_sum(Vec3 xi, int m, const Vec3* y, const Vec3* f,
                                 Pair pair) {
  __shared__ double ty[3 * kBlock], tf[3 * kBlock];
  Vec3 sum;
  for (int start = 0; start < m; start += kBlock) {
    const int k = start + threadIdx.x;
    if (k < m) {
      ty[3 * threadIdx.x] = y[k].x, ty[3 * threadIdx.x + 1] = y[k].y;
      ty[3 * threadIdx.x + 2] = y[k].z;
      tf[3 * threadIdx.x] = f[k].x, tf[3 * threadIdx.x + 1] = f[k].y;
      tf[3 * threadIdx.x + 2] = f[k].z;
    }
    __syncthreads();
    const int count = min(kBlock, m - start);
    for (int j = 0; j < count; ++j)
      sum += pair(xi - Vec3{ty[3 * j], ty[3 * j + 1], ty[3 * j + 2]},
                  Vec3{tf[3 * j], tf[3 * j + 1], tf[3 * j + 2]});
    __syncthreads();
  }
  return sum;
}

__global__ void free_far_sum_kernel(int n, const Vec3* x, int m, const Vec3* y,
                                    const Vec3* f, Vec3* u) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  // Threads past n still help to stage tiles; they only skip the store.
  const Vec3 xi = i < n ? x[i] : Vec3{1e300, 0, 0};
  const Vec3 sum =
      tiled_source_sum(xi, m, y, f, [](Vec3 r, Vec3 q) { return stokeslet_apply(r, q); });
  if (i < n)
    u[i] = sum;
}

__global__ void screened_far_sum_kernel(ShearedLattice g, double xi_ewald, double r_cut,
                                        int n, const Vec3* x, int m, const Vec3* y,
                                        const Vec3* f, Vec3* u) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  const Vec3 xi = i < n ? x[i] : Vec3{};
  const double rc2 = r_cut * r_cut;
  const Vec3 sum = tiled_source_sum(xi, m, y, f, [&](Vec3 r, Vec3 q) {
    r = wrap_to_cell(g, r);
    return dot(r, r) < rc2 ? ewald_real_apply(r, q, xi_ewald) : Vec3{};
  });
  if (i < n)
    u[i] = sum;
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
  binned_screened_kernel<<<blocks_for(n), kBlock>>>(b, xi, r_cut, n, x, ys, fs, u);
  check_launch("binned_screened_sum");
}

void binned_near_corrections(const CellBins& b, const MeshView& mesh, const Vec3* x,
                             const int* tri, const Vec3* wc, const TriangleLoad* loads,
                             NearRule rule, Vec3* u) {
  binned_near_kernel<<<blocks_for(mesh.num_nodes()), kBlock>>>(b, mesh, x, tri, wc, loads,
                                                               rule, u);
  check_launch("binned_near_corrections");
}

void free_far_sum(int n, const Vec3* x, int m, const Vec3* y, const Vec3* f, Vec3* u) {
  free_far_sum_kernel<<<blocks_for(n), kBlock>>>(n, x, m, y, f, u);
  check_launch("free_far_sum");
}

void free_near_corrections(const MeshView& mesh, const Vec3* x, const TriangleLoad* loads,
                           const TriangleBounds* bounds, NearRule rule, Vec3* u) {
  free_near_kernel<<<blocks_for(mesh.num_nodes()), kBlock>>>(mesh, x, loads, bounds, rule,
                                                             u);
  check_launch("free_near_corrections");
}

void screened_far_sum(const ShearedLattice& g, double xi, double r_cut, int n,
                      const Vec3* x, int m, const Vec3* y, const Vec3* f, Vec3* u) {
  screened_far_sum_kernel<<<blocks_for(n), kBlock>>>(g, xi, r_cut, n, x, m, y, f, u);
  check_launch("screened_far_sum");
}

void periodic_near_corrections(const ShearedLattice& g, const MeshView& mesh,
                               const Vec3* x, const TriangleLoad* loads, NearRule rule,
                               Vec3* u) {
  periodic_near_kernel<<<blocks_for(mesh.num_nodes()), kBlock>>>(g, mesh, x, loads, rule,
                                                                 u);
  check_launch("periodic_near_corrections");
}

} // namespace capsim::cuda
