#pragma once
// The double layer K[u] of M capsules (one topology, P1 geometry and P1 density u) in
// the sheared periodic box (cells/sheared_lattice.hpp), in the normalisation and sign of
// the free-space K (double_layer.hpp):
//   K[u](x) = 1/(8 pi) sum_m PV int_{A_m} u_i(y) T^per_ijk(x - y) n_k(y) dA(y),
// T^per the periodic stresslet of ewald_stresslet.hpp (3), by plain Ewald sums:
//  - the 3-point far rule for every triangle, with T^per split into
//    - real space: every rule point and image within r_cut, the screened T^R, through
//      cell lists (PeriodicCells);
//    - reciprocal space: summed directly over the half of 0 < |k| < k_cut of the sheared
//      reciprocal lattice, O((N + N_src) K) (as ewald_reciprocal_direct does for the
//      single layer), or, given SpectralParameters, by Spectral Ewald (af Klinteberg &
//      Tornberg 2014; SpectralStresslet, spectral_ewald.hpp), O(N P^3 + M^3 log M);
//  - near corrections (triangle images closer than far_ratio diameters to a node): the
//    free-space correction of double_layer_near_correction, right for every xi because
//    T^per - T is smooth (as for the single layer, periodic_single_layer.hpp), set up
//    once as matrices of the vertex densities (double_layer_near_matrices).
// The split is exact up to the Ewald truncation whatever xi is. The cut-offs are those
// of the single layer's EwaldParameters (choose_ewald_parameters): the stresslet's real
// terms decay like erfc(x) + 2x/sqrt(pi) (1 + 2x^2/3) exp(-x^2) relative to T, its
// reciprocal ones like (1 + q) exp(-q), both below the stokeslet's bounds.
//
// The k = 0 term. T^_ijk(k) is odd and of degree -1 at k = 0, so it has no limit there;
// we set it to zero, the only value that keeps T^per odd, T^per(-r) = -T^per(r), as T is
// (and as the single layer's omitted k = 0 keeps the periodic stokeslet even with zero
// mean). Then T^per has zero mean over the box and
//   -d/dr_k T^per_ijk(r) = 8 pi d_ij (sum_n delta(r - x_n) - 1/V),
// (Fourier: -i k_k T^_ijk = 8 pi d_ij for every k != 0, and nothing at k = 0), so by the
// divergence theorem, for a capsule c of volume V_c,
//   1/(8 pi) int_{A_c} T^per_ijk(x - y) n_k(y) dA(y)
//     = d_ij (1 - V_c/V) inside, d_ij (1/2 - V_c/V) on A_c (principal value),
//       -d_ij V_c/V outside:                                                      (4)
// a constant density c on capsule c gives K = c (1/2 - V_c/V) on its own surface and
// -c V_c/V everywhere outside it (its images included), no longer c/2 and 0. Consequence
// for the interface equation u - kappa K[u] = f (second_kind_solve.hpp): the field that
// the periodic representation builds has the box mean of u_inf; the mean of the true
// velocity differs from it by (1 - lambda)/V sum_m int_{V_m} u dV, a uniform
// translation of the whole suspension (a Galilean frame, no effect on the rheology). A
// solver wanting the zero-mean frame adds that constant.
//
// Evaluation at the nodes (singularity subtraction, as the free-space code): for node
// x_i of capsule c,
//   8 pi K[u](x_i) = int_{A_c} (u - u(x_i)) T^per n dA + sum_{m != c} int_{A_m} u T^per n
//                    dA + 8 pi (1/2 - V_c/V) u(x_i),
// the subtracted constant's integral by (4) with V_c the volume of the P1 polyhedron, so
// that a constant (a rigid translation of one capsule) is mapped exactly to
// (1/2 - V_c/V) u. The subtracted term's far-rule part, sum over capsule c's rule points
// and all their images of T^per(x_i - y_g) a_g, is a geometry-only 3 x 3 matrix per node
// set up once.
#include "mesh/icosphere.hpp"
#include "stokes/cells/periodic_cells.hpp"
#include "stokes/double_layer/double_layer.hpp"
#include "stokes/ewald/spectral_ewald.hpp"
#include "stokes/kernels/periodic_stokeslet.hpp"
#include "stokes/single_layer/single_layer.hpp"

#include <memory>
#include <vector>

namespace capsim {

// The periodic double layer of one geometry, set up once and applied to many densities.
class PeriodicDoubleLayer {
public:
  // x: num_capsules * topo.num_nodes positions, capsule after capsule (copied, as are
  // the topology, lattice and parameters). ewald: xi and the cut-offs (r_cut, k_cut).
  // spectral: null for the direct reciprocal sums (the reference), else the grid of the
  // Spectral Ewald reciprocal sums of apply() and of the self matrices
  // (choose_stresslet_spectral_parameters with the same ewald).
  // self_ewald, self_grid: with spectral, the split and grid of the self matrices' sums
  // where they differ from apply()'s (both or neither): one grid pass per capsule makes
  // them cost most at large M, and a smaller xi coarsens that grid (the real-space part
  // then reaches further over the capsule's own points). The matrices are the same up
  // to the Ewald truncation whatever the split.
  PeriodicDoubleLayer(const Topology& topo, int num_capsules, const std::vector<Vec3>& x,
                      const ShearedLattice& lattice, const EwaldParameters& ewald,
                      const QuadratureOptions& quad,
                      const SpectralParameters* spectral = nullptr,
                      const EwaldParameters* self_ewald = nullptr,
                      const SpectralParameters* self_grid = nullptr);

  int num_nodes() const { return int(x_.size()); }
  int num_capsules() const { return num_capsules_; }
  // The enclosed volume of capsule c's P1 polyhedron, the V_c of (4).
  double capsule_volume(int c) const { return volume_[c]; }
  long num_wave_vectors() const { return long(k_.size()); } // half of 0 < |k| < k_cut

  // k = K[u] at the nodes (u: one vector per node, else std::invalid_argument). With
  // subtract = false the self capsule is integrated without singularity subtraction (the
  // plain principal value of the polyhedron, for tests).
  void apply(const std::vector<Vec3>& u, std::vector<Vec3>& k,
             bool subtract = true) const;

private:
  struct NearImage {
    int triangle;
    Vec3 shift; // lattice vector from the triangle to its image (exactly 0: itself)
  };

  void setup_near_lists();
  void setup_near_matrices();
  void setup_self_matrices(const EwaldParameters* self_ewald,
                           const SpectralParameters* self_grid);
  void add_self_real_space(const EwaldParameters& ew);
  void add_self_reciprocal_direct();
  std::vector<Vec3> rule_densities(const std::vector<Vec3>& u) const;
  // The far-rule sum over all points and images, real and reciprocal parts, at each node.
  void add_real_space(const std::vector<Vec3>& ug, std::vector<Vec3>& sum) const;
  void add_reciprocal(const std::vector<Vec3>& ug, std::vector<Vec3>& sum) const;
  Vec3 near_correction(int i, const std::vector<Vec3>& u, Vec3 sub) const;

  Topology topo_;
  int num_capsules_;
  std::vector<Vec3> x_;
  ShearedLattice lattice_;
  EwaldParameters ewald_;
  QuadratureOptions quad_;
  std::vector<double> volume_; // per capsule
  DoubleLayerTriangles tri_;
  PeriodicCells cells_; // the rule points, for the real-space sum
  // Half of the wave vectors 0 < |k| < k_cut and their screening phi(k).
  std::vector<Vec3> k_;
  std::vector<double> phi_;
  // The Spectral Ewald grid of add_reciprocal and setup_self_matrices, or null (direct
  // sums). Its grids are work space: apply() is not reentrant with it.
  std::unique_ptr<SpectralStresslet> spectral_;
  // Per node: sum over its own capsule's rule points and images of T^per(x_i - y_g) a_g
  // (xx, yy, zz, xy, xz, yz), the far part of the subtracted term.
  std::vector<double> self_[6];
  std::vector<int> near_offset_;
  std::vector<NearImage> near_;
  // Per near pair the correction's matrices of its triangle's three vertex densities
  // (double_layer_near_matrices), 18 numbers.
  std::vector<double> near_matrix_;
};

// One-shot form: k = K[u] at the nodes of M capsules in the periodic box.
void periodic_double_layer_velocity(const Topology& topo, int num_capsules,
                                    const std::vector<Vec3>& x,
                                    const std::vector<Vec3>& u,
                                    const ShearedLattice& lattice,
                                    const EwaldParameters& ewald,
                                    const QuadratureOptions& quad, std::vector<Vec3>& k);

} // namespace capsim
