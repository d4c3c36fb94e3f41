#pragma once
// The surface velocity u of capsules whose interior viscosity is lambda times the
// exterior's, from the boundary-integral equation of the second kind (Pozrikidis 1992,
// "Boundary integral and singularity methods", ch. 5, written with K of
// double_layer.hpp):
//   u - kappa K[u] = f,   kappa = 2 (lambda - 1)/(lambda + 1),
//   f = 2/(1 + lambda) (u_inf + u_SL),
// solved matrix-free by Eigen's GMRES (unsupported/Eigen/IterativeSolvers).
//
// Why deflation: on each capsule the rigid-body motions are eigenfunctions of K with
// eigenvalue 1/2 and the normal vector n is an eigenfunction of its adjoint with
// eigenvalue -1/2 (the flux identity int n . K[u] dA = -1/2 int n . u dA). So I - kappa K
// has the eigenvalues 2/(1 + lambda) (-> 0 as lambda -> oo) and 2 lambda/(1 + lambda)
// (-> 0 as lambda -> 0), and GMRES slows down at both ends (Pozrikidis 1992, ch. 4 on the
// spectrum of the double-layer operator and Wielandt's deflation, ch. 6 on its use for
// lambda != 1; Zinchenko, Rother & Davis 1997, Phys. Fluids 9, 1493).
//
// Wielandt/Hotelling deflation, per capsule, in the surface inner product (u, v) =
// sum_i a_i u_i . v_i (a_i the lumped node areas):
//   K_d[w] = K[w] - 1/2 P[w] + 1/2 N[w],
// P the orthogonal projection on the 6 rigid-body motions, N[w] = m (m, w)/(m, m) with
// m_i = nu_i / a_i, nu_i = (node_area_vectors)_i / 6, so that (m, w) = sum_i nu_i . w_i
// is exactly the rate of change of the P1 volume, and (m, v) = 0 exactly for every
// rigid-body motion v of the polyhedron (sum nu_i = 0, sum x_i x nu_i = 0 by the
// divergence theorem). K_d maps the rigid-body motions to 0 and has n as a left null
// vector; the rest of K's spectrum is kept (block-triangular form in R + R^perp, and
// Brauer's theorem for the rank-one left update). Then one solves
//   w - kappa K_d[w] = f,   and   u = w + (lambda - 1)/2 P[w]
// solves the original equation: (I - kappa K) P w = (1 - kappa/2) P w, and (m, w) =
// (m, f) = 0 for a volume-conserving f (u_inf and u_SL are divergence free), so
// (I - kappa K) u = f - kappa/2 P w + (1 - kappa/2)(lambda - 1)/2 P w = f, as
// (1 - kappa/2)(lambda - 1)/2 = kappa/2. Discretely, on a capsule's own surface, the
// rigid-body part is exact too: with the singularity subtraction K maps a translation to
// itself/2 by construction and a rotation as well, its subtracted density
// Omega x (y - x) being perpendicular to r = x - y; and (m, w) = (m, f) rests on the flux
// identity, which the discrete K holds to O(h^2). Across capsules K of one capsule's
// rigid motion vanishes on the others only to the quadrature error e, so there u meets
// the undeflated equation up to kappa (lambda - 1)/2 e: measured 3e-7, 3e-6 and 4e-4
// of |f| at lambda = 0.1, 10 and 1000 for two unit spheres 0.4 apart at level 3, below
// the discretisation error (5e-3 at level 3 in the drop test).
//
// In the sheared periodic box (periodic_double_layer.hpp) a rigid translation t of one
// capsule is no longer an eigenfunction: K maps it to t/2 less (V_m/V) t on every
// capsule, V_m its volume and V the box's; rotations about the volume centroids still
// go to half themselves. So P there is the oblique projection on the rigid-body motions
// whose translations have zero volume-weighted sum (P[w] less its mean translation on
// every capsule; still a projection, and K P = P/2 exactly): the collective translation
// is left in the operator, where its eigenvalue 1/2 - phi keeps I - kappa K_d at least
// 2/(1 + lambda) + kappa phi. The flux identity becomes int_{A_c} n . K[u] dA =
// -1/2 int_{A_c} n . u dA + (V_c/V) sum_m int_{A_m} n . u dA, and (m, w) = 0 on every
// capsule follows as before (summing over the capsules, (1 - kappa phi) sum_m (m_m, w) =
// 0), so u = w + (lambda - 1)/2 P[w] again solves the original equation.
//
// Measured on a sphere (level 3, tolerance 1e-10, lambda 0.001-1000): 6-8 GMRES
// iterations with deflation, 7-11 without; on an ellipsoid 1.5 : 1 : 0.6, 11-16 with and
// 11-20 without. The spectrum left after deflation, [-0.08, 0.31] on the sphere, keeps
// I - kappa K_d within [0.38, 1.62] for every lambda.
#include "stokes/double_layer/double_layer.hpp"
#include "stokes/double_layer/periodic_double_layer.hpp"

#include <Eigen/Core>
#include <Eigen/Dense>
#include <functional>
#include <vector>

namespace capsim {

// kappa of the equation above: 0 at lambda = 1, -> 2 as lambda -> oo, -2 as lambda -> 0.
inline double second_kind_kappa(double lambda) {
  return 2.0 * (lambda - 1.0) / (lambda + 1.0);
}

struct SecondKindOptions {
  // GMRES stops when ||f - A w|| <= tolerance ||f|| (Euclidean norm over the 3N values of
  // the equation that is solved: the deflated one when deflate is set).
  double tolerance = 1e-8;
  int max_iterations = 300;
  int restart = 100; // Krylov vectors kept before a restart
  bool deflate = true;
};

struct SecondKindResult {
  int iterations = 0;    // GMRES iterations (one application of K each)
  double residual = 0;   // ||f - A w|| / ||f|| reached (GMRES's estimate)
  bool converged = true; // residual <= tolerance
  // Wall seconds: setting the double layer up for this geometry (near lists, self
  // matrices), and applying it (once for the first residual, once per iteration).
  double setup_seconds = 0;
  double apply_seconds = 0;
};

// k = K[u] at the nodes: the free-space or the periodic double layer of one geometry.
using DoubleLayerApply =
    std::function<void(const std::vector<Vec3>& u, std::vector<Vec3>& k)>;

// The operator w -> A w = w - kappa K_d[w] (or w - kappa K[w] without deflation) of M
// capsules, with the maps between the deflated unknown w and the velocity u.
class SecondKindOperator {
public:
  // k must belong to the same topology, capsules and positions; box_volume: that of the
  // periodic box whose double layer k is (0: unbounded fluid).
  SecondKindOperator(DoubleLayerApply k, const Topology& topo, int num_capsules,
                     const std::vector<Vec3>& x, double lambda, bool deflate,
                     double box_volume = 0);
  // The free-space double layer k, which must outlive this object.
  SecondKindOperator(const DoubleLayer& k, const Topology& topo, int num_capsules,
                     const std::vector<Vec3>& x, double lambda, bool deflate);

  int size() const { return 3 * num_nodes_; }
  double kappa() const { return kappa_; }

  // y = A w (size() values each, node after node).
  void apply(const Eigen::VectorXd& w, Eigen::VectorXd& y) const;
  // y = K_d[w] (or K[w] without deflation), for tests of the spectrum.
  void apply_kernel(const Eigen::VectorXd& w, Eigen::VectorXd& y) const;
  // y = P[w], the projection on each capsule's rigid-body motions (in a periodic box
  // less their volume-weighted mean translation).
  void rigid_projection(const Eigen::VectorXd& w, Eigen::VectorXd& y) const;
  // y = N[w], the projection on each capsule's normal mode m.
  void normal_projection(const Eigen::VectorXd& w, Eigen::VectorXd& y) const;
  // u = w + (lambda - 1)/2 P[w], and its inverse w = u - (lambda - 1)/(lambda + 1) P[u].
  Eigen::VectorXd velocity_of(const Eigen::VectorXd& w) const;
  Eigen::VectorXd unknown_of(const Eigen::VectorXd& u) const;

private:
  DoubleLayerApply k_;
  int num_nodes_, nodes_per_capsule_, num_capsules_;
  double lambda_, kappa_;
  bool deflate_;
  bool periodic_;              // the collective translation stays out of P
  std::vector<double> volume_; // per capsule, the P1 polyhedron's
  std::vector<double> area_;   // lumped node areas a_i
  std::vector<Vec3> centre_;   // per capsule, the volume centroid (rotations' pivot)
  std::vector<Eigen::Matrix<double, 6, 6>> gram_inverse_; // per capsule
  std::vector<Vec3> nu_;                                  // nu_i = node area vector / 6
  std::vector<double> normal_norm2_; // per capsule, (m, m) = sum |nu_i|^2 / a_i
  std::vector<Vec3> positions_;      // the nodes, for the rotation modes
};

// The sheared periodic box of a suspension: its lattice, Ewald parameters and, for
// Spectral-Ewald reciprocal sums, their grid (null: plain Ewald sums).
struct SecondKindBox {
  ShearedLattice lattice;
  EwaldParameters ewald;
  const SpectralParameters* spectral = nullptr;
  // With spectral, the self matrices' own split (PeriodicDoubleLayer), or null.
  const EwaldParameters* self_ewald = nullptr;
  const SpectralParameters* self_grid = nullptr;
};

// Solves u - kappa K[u] = f at the nodes of M capsules (lambda > 0 and finite, else
// std::invalid_argument), in unbounded fluid or (box) in the periodic box. u: on entry
// the initial guess (for example the previous step's velocity; resized to zeros if
// empty), on exit the solution. At lambda = 1 (kappa = 0) u = f exactly, with no
// iteration.
SecondKindResult solve_second_kind(const Topology& topo, int num_capsules,
                                   const std::vector<Vec3>& x, double lambda,
                                   const std::vector<Vec3>& f,
                                   const QuadratureOptions& quadrature,
                                   const SecondKindOptions& options, std::vector<Vec3>& u,
                                   const SecondKindBox* box = nullptr);

} // namespace capsim
