// Membrane forces, traction, triangle sources and the Runge-Kutta update on the device:
// launch code around membrane/tension_field.hpp (the neo-Hookean element or its
// relaxation), membrane/bending.hpp and stokes/quadrature/element_integrals.hpp.
#include "cuda/device_kernels.hpp"
#include "cuda/launch.cuh"
#include "mesh/surface_geometry.hpp"

namespace capsim::cuda {
namespace {

__global__ void element_forces_kernel(MeshView mesh, double gs, bool wrinkling,
                                      const Vec3* x, Vec3* corner_grad, double* area) {
  const int e = blockIdx.x * blockDim.x + threadIdx.x;
  if (e >= mesh.num_triangles())
    return;
  const int local = e % mesh.tri_per_capsule;
  const int base = (e / mesh.tri_per_capsule) * mesh.nodes_per_capsule;
  const int* t = mesh.triangles + 3 * local;
  const Vec3 x0 = x[base + t[0]], x1 = x[base + t[1]], x2 = x[base + t[2]];
  Vec3 g[3];
  membrane_element(mesh.refs[local], gs, wrinkling, x0, x1, x2, g);
  for (int k = 0; k < 3; ++k)
    corner_grad[3 * e + k] = g[k];
  area[e] = 0.5 * norm(area_vector2(x0, x1, x2));
}

__global__ void hinge_forces_kernel(MeshView mesh, double kb, const Vec3* x,
                                    Vec3* hinge_grad) {
  const int h = blockIdx.x * blockDim.x + threadIdx.x;
  if (h >= mesh.num_hinges())
    return;
  const int local = h % mesh.hinges_per_capsule;
  const int base = (h / mesh.hinges_per_capsule) * mesh.nodes_per_capsule;
  const int* n = mesh.hinges + 4 * local;
  Vec3 g[4];
  bending_hinge(mesh.hinge_refs[local], kb, x[base + n[0]], x[base + n[1]],
                x[base + n[2]], x[base + n[3]], g);
  for (int k = 0; k < 4; ++k)
    hinge_grad[4 * h + k] = g[k];
}

// A gather over each node's corners instead of atomics: the sum runs in a fixed order,
// so results are reproducible and match the CPU assembly to rounding.
__global__ void gather_nodes_kernel(MeshView mesh, const Vec3* corner_grad,
                                    const double* area, const Vec3* hinge_grad,
                                    const Vec3* extra, bool lumped_load, Vec3* out) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= mesh.num_nodes())
    return;
  const int a = i % mesh.nodes_per_capsule;
  const int tri_base = (i / mesh.nodes_per_capsule) * mesh.tri_per_capsule;
  Vec3 g;
  double node_area = 0;
  for (int j = mesh.node_corner_offset[a]; j < mesh.node_corner_offset[a + 1]; ++j) {
    const int e = tri_base + mesh.node_corner[j] / 3, k = mesh.node_corner[j] % 3;
    g += corner_grad[3 * e + k];
    node_area += area[e] / 3.0;
  }
  if (hinge_grad) {
    const int capsule_base = 4 * (i / mesh.nodes_per_capsule) * mesh.hinges_per_capsule;
    for (int j = mesh.node_hinge_offset[a]; j < mesh.node_hinge_offset[a + 1]; ++j)
      g += hinge_grad[capsule_base + mesh.node_hinge[j]];
  }
  if (extra) // after the element sum, as the CPU adds the repulsion to its gradient
    g += extra[i];
  out[i] = lumped_load ? (1.0 / node_area) * g : g;
}

__global__ void triangle_sources_kernel(MeshView mesh, const Vec3* x, const Vec3* q,
                                        TriangleLoad* loads, TriangleBounds* bounds,
                                        Vec3* y, Vec3* f) {
  const int e = blockIdx.x * blockDim.x + threadIdx.x;
  if (e >= mesh.num_triangles())
    return;
  const int local = e % mesh.tri_per_capsule;
  const int base = (e / mesh.tri_per_capsule) * mesh.nodes_per_capsule;
  TriangleLoad t;
  for (int k = 0; k < 3; ++k) {
    t.p[k] = x[base + mesh.triangles[3 * local + k]];
    t.q[k] = q[base + mesh.triangles[3 * local + k]];
  }
  loads[e] = t;
  bounds[e] = {triangle_centroid(t.p), triangle_diameter(t.p)};
  const TriangleRule rule = triangle_rule_3();
  const double a = 0.5 * norm(area_vector2(t.p[0], t.p[1], t.p[2]));
  for (int g = 0; g < rule.n; ++g) {
    y[3 * e + g] = barycentric(t.p, rule.l1[g], rule.l2[g]);
    f[3 * e + g] = (rule.w[g] * a) * barycentric(t.q, rule.l1[g], rule.l2[g]);
  }
}

__global__ void finish_velocity_kernel(int n, const Vec3* x, double shear_rate, Vec3* u) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n)
    return;
  Vec3 v = (-1.0 / (8.0 * kPi)) * u[i];
  v.x += shear_rate * x[i].y;
  u[i] = v;
}

} // namespace

void element_forces(const MeshView& mesh, double gs, bool wrinkling, const Vec3* x,
                    Vec3* corner_grad, double* area) {
  CAPSIM_LAUNCH(element_forces_kernel, blocks_for(mesh.num_triangles()), kBlock)
  (mesh, gs, wrinkling, x, corner_grad, area);
  check_launch("element_forces");
}

void hinge_forces(const MeshView& mesh, double kb, const Vec3* x, Vec3* hinge_grad) {
  CAPSIM_LAUNCH(hinge_forces_kernel, blocks_for(mesh.num_hinges()), kBlock)
  (mesh, kb, x, hinge_grad);
  check_launch("hinge_forces");
}

void gather_nodes(const MeshView& mesh, const Vec3* corner_grad, const double* area,
                  const Vec3* hinge_grad, const Vec3* extra, bool lumped_load,
                  Vec3* out) {
  CAPSIM_LAUNCH(gather_nodes_kernel, blocks_for(mesh.num_nodes()), kBlock)
  (mesh, corner_grad, area, hinge_grad, extra, lumped_load, out);
  check_launch("gather_nodes");
}

void triangle_sources(const MeshView& mesh, const Vec3* x, const Vec3* q,
                      TriangleLoad* loads, TriangleBounds* bounds, Vec3* y, Vec3* f) {
  CAPSIM_LAUNCH(triangle_sources_kernel, blocks_for(mesh.num_triangles()), kBlock)
  (mesh, x, q, loads, bounds, y, f);
  check_launch("triangle_sources");
}

void finish_velocity(int n, const Vec3* x, double shear_rate, Vec3* u) {
  CAPSIM_LAUNCH(finish_velocity_kernel, blocks_for(n), kBlock)(n, x, shear_rate, u);
  check_launch("finish_velocity");
}

} // namespace capsim::cuda
