#pragma once
// Launchers of the CUDA kernels (defined in the .cu files next to this one). Plain C++
// declarations over device pointers, so that the host side (device_flow.cpp) is ordinary
// C++. Every kernel is a loop over targets or sources around a host-device function of
// membrane/ or stokes/; all run on the default stream, in order.
#include "membrane/bending.hpp"
#include "membrane/tension_field.hpp"
#include "stokes/cells/cell_bins.hpp"
#include "stokes/cells/sheared_lattice.hpp"
#include "stokes/ewald/spectral_weights.hpp"
#include "stokes/quadrature/element_integrals.hpp"
#include "stokes/quadrature/near_corrections.hpp"

namespace capsim::cuda {

// The mesh of M capsules sharing one topology, in device memory. Global node i is node
// i % nodes_per_capsule of capsule i / nodes_per_capsule; triangles likewise.
struct MeshView {
  const int* triangles = nullptr;          // 3 local node indices per triangle
  const ElementReference* refs = nullptr;  // reference state per triangle
  const int* node_corner_offset = nullptr; // node a's corners: [offset[a], offset[a+1])
  const int* node_corner = nullptr;        // 3 * triangle + corner, one capsule
  // The bending hinges (membrane/bending.hpp), none without bending: 4 local nodes
  // (a, b, c, d) and the reference of each, and each node's hinge corners as above.
  const int* hinges = nullptr;
  const HingeReference* hinge_refs = nullptr;
  const int* node_hinge_offset = nullptr;
  const int* node_hinge = nullptr; // 4 * hinge + corner, one capsule
  int tri_per_capsule = 0, nodes_per_capsule = 0, hinges_per_capsule = 0, capsules = 0;
  CAPSIM_HD int num_triangles() const { return tri_per_capsule * capsules; }
  CAPSIM_HD int num_nodes() const { return nodes_per_capsule * capsules; }
  CAPSIM_HD int num_hinges() const { return hinges_per_capsule * capsules; }
};

// Each triangle's centroid and diameter (the near test).
struct TriangleBounds {
  Vec3 centroid;
  double diameter = 0;
};

// --- membrane_kernels.cu ---------------------------------------------------------------
// dW/dx of every element at its three corners (corner_grad[3 e + k]) and its area; W
// the neo-Hookean energy, or its relaxation with wrinkling (membrane_element).
void element_forces(const MeshView& mesh, double gs, bool wrinkling, const Vec3* x,
                    Vec3* corner_grad, double* area);
// dE/dx of every bending hinge at its four nodes (hinge_grad[4 h + k]), kb the bending
// modulus (bending_hinge).
void hinge_forces(const MeshView& mesh, double kb, const Vec3* x, Vec3* hinge_grad);
// Per node: the sum of its corners' gradients, then of its hinge corners' where
// hinge_grad is not null, then extra[i] where extra is not null (the repulsion's
// gradient): the CPU's order; divided by the lumped node area (a third of the adjacent
// triangles' areas) when lumped_load, which gives the traction q.
void gather_nodes(const MeshView& mesh, const Vec3* corner_grad, const double* area,
                  const Vec3* hinge_grad, const Vec3* extra, bool lumped_load, Vec3* out);
// Per triangle: its corners and loads, its bounds, and its 3-point rule as point sources
// (y[3 e + g], f[3 e + g] = w_g A q(y_g)).
void triangle_sources(const MeshView& mesh, const Vec3* x, const Vec3* q,
                      TriangleLoad* loads, TriangleBounds* bounds, Vec3* y, Vec3* f);
// u <- -u / (8 pi) + (shear_rate x.y, 0, 0): the single-layer factor and the shear flow.
void finish_velocity(int n, const Vec3* x, double shear_rate, Vec3* u);

// --- single_layer_kernels.cu -----------------------------------------------------------
// u[i] = sum_g J(x_i - y_g) f_g over all m point sources (free space).
void free_far_sum(int n, const Vec3* x, int m, const Vec3* y, const Vec3* f, Vec3* u);
// u[i] += the free-space near corrections of every triangle near x_i.
void free_near_corrections(const MeshView& mesh, const Vec3* x, const TriangleLoad* loads,
                           const TriangleBounds* bounds, NearRule rule, Vec3* u);
// u[i] = sum_g J^EI(x_i - y_g) f_g over the sources whose nearest image is within r_cut;
// needs r_cut < L/3, where that image is the only one (device_flow.cpp checks).
void screened_far_sum(const ShearedLattice& g, double xi, double r_cut, int n,
                      const Vec3* x, int m, const Vec3* y, const Vec3* f, Vec3* u);
// u[i] += the near corrections of the nearest image of every triangle (free-space rule:
// see periodic_single_layer.hpp).
void periodic_near_corrections(const ShearedLattice& g, const MeshView& mesh,
                               const Vec3* x, const TriangleLoad* loads, NearRule rule,
                               Vec3* u);

// u[i] = the screened real-space sum at x_i over binned sources (binned_sums.hpp; ys, fs
// in bin order, bins at least r_cut wide).
void binned_screened_sum(const CellBins& b, double xi, double r_cut, int n, const Vec3* x,
                         const Vec3* ys, const Vec3* fs, Vec3* u);
// u[i] += the near corrections at x_i of the binned triangle images near it (entry j:
// triangle tri[j], centroid wrapped to wc[j]).
void binned_near_corrections(const CellBins& b, const MeshView& mesh, const Vec3* x,
                             const int* tri, const Vec3* wc, const TriangleLoad* loads,
                             NearRule rule, Vec3* u);

// --- binning_kernels.cu ----------------------------------------------------------------
// Bins `count` points p into n^3 cells: order[j] is the point of binned entry j (key and
// scratch are work space of `count` entries), wrapped[j] its wrapped position, and
// start (n^3 + 1 entries) the offsets of the cells, as CellBins reads them.
void bin_points(const ShearedLattice& g, int n, int count, const Vec3* p, int* key,
                int* order, Vec3* scratch, Vec3* wrapped, int* start);
// out[j] = in[order[j]]
void gather_by_order(int count, const int* order, const Vec3* in, Vec3* out);
// The largest triangle diameter, and the centroids.
double max_diameter(int count, const TriangleBounds* bounds);
void centroids_of(int count, const TriangleBounds* bounds, Vec3* out);

// --- spectral_kernels.cu ---------------------------------------------------------------
// grid[a * M^3 + j] += sum_k g(z_j - y_k) f_k.a (M^3 = grid_points(s); grid zeroed by
// the caller; atomics).
void spread(const SpreadGrid& s, const ShearedLattice& g, int count, const Vec3* y,
            const Vec3* f, double* grid);
// Scales the r2c spectra of the three components (interleaved re, im; spectrum_modes(s)
// modes per component) by the multiplier times c.
void scale_spectrum(const ShearedLattice& g, const SpreadGrid& s, double xi, double c,
                    double* spectrum);
// u[i] += cell sum_j g(x_i - z_j) grid(z_j)
void gather(const SpreadGrid& s, const ShearedLattice& g, int n, const Vec3* x,
            const double* grid, double cell, Vec3* u);

} // namespace capsim::cuda
