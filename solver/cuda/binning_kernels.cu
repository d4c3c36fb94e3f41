// Binning on the device (stokes/cells/cell_bins.hpp): each point's cell and wrapped position,
// a sort by cell (CCCL/Thrust), and the cell offsets by binary search.
#include "cuda/device_kernels.hpp"
#include "cuda/launch.cuh"

#include <thrust/binary_search.h>
#include <thrust/execution_policy.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/sequence.h>
#include <thrust/sort.h>
#include <thrust/transform_reduce.h>

namespace capsim::cuda {
namespace {

__global__ void bin_kernel(ShearedLattice g, int n, int count, const Vec3* p, int* key,
                           Vec3* wrapped) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < count)
    key[i] = bin_of(g, n, p[i], wrapped[i]);
}

__global__ void gather_kernel(int count, const int* order, const Vec3* in, Vec3* out) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j < count)
    out[j] = in[order[j]];
}

__global__ void centroid_kernel(int count, const TriangleBounds* b, Vec3* out) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j < count)
    out[j] = b[j].centroid;
}

struct Diameter {
  __device__ double operator()(const TriangleBounds& b) const { return b.diameter; }
};
struct Max {
  __device__ double operator()(double a, double b) const { return a > b ? a : b; }
};

} // namespace

void bin_points(const ShearedLattice& g, int n, int count, const Vec3* p, int* key,
                int* order, Vec3* scratch, Vec3* wrapped, int* start) {
  CAPSIM_LAUNCH(bin_kernel, blocks_for(count), kBlock)(g, n, count, p, key, scratch);
  check_launch("bin_points");
  thrust::sequence(thrust::device, order, order + count);
  // A stable sort keeps each cell's points in index order: the same sums on every run.
  thrust::stable_sort_by_key(thrust::device, key, key + count, order);
  gather_by_order(count, order, scratch, wrapped);
  const int cells = n * n * n;
  thrust::lower_bound(thrust::device, key, key + count, thrust::counting_iterator<int>(0),
                      thrust::counting_iterator<int>(cells + 1), start);
}

void gather_by_order(int count, const int* order, const Vec3* in, Vec3* out) {
  CAPSIM_LAUNCH(gather_kernel, blocks_for(count), kBlock)(count, order, in, out);
  check_launch("gather_by_order");
}

double max_diameter(int count, const TriangleBounds* bounds) {
  return thrust::transform_reduce(thrust::device, bounds, bounds + count, Diameter{}, 0.0,
                                  Max{});
}

void centroids_of(int count, const TriangleBounds* bounds, Vec3* out) {
  CAPSIM_LAUNCH(centroid_kernel, blocks_for(count), kBlock)(count, bounds, out);
  check_launch("centroids_of");
}

} // namespace capsim::cuda
