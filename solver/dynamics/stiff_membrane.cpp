#include "dynamics/stiff_membrane.hpp"

#include "stokes/self_mobility.hpp"

#include <Eigen/LU>
#include <Eigen/SparseLU>
#include <stdexcept>

namespace capsim {

StiffMembrane::StiffMembrane(const Membrane& membrane, int num_capsules,
                             QuadratureOptions quadrature)
    : membrane_(membrane), num_capsules_(num_capsules), quadrature_(quadrature),
      systems_(num_capsules) {}

Eigen::SparseMatrix<double> StiffMembrane::jacobian(const Vec3* xc,
                                                    HessianPart part) const {
  const Topology& topo = membrane_.topology();
  std::vector<Vec3> grad;
  membrane_.energy_gradient(xc, grad);
  const Matrix dq = membrane_.load_jacobian(xc, grad, part);
  const std::vector<Mat3> b = self_mobility_blocks(topo, xc, quadrature_);
  // Row block i of B dq/dx is B_i times row block i of dq/dx.
  Matrix blocks(dq.rows(), dq.cols());
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(9 * topo.num_nodes);
  for (int i = 0; i < topo.num_nodes; ++i)
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        trip.emplace_back(3 * i + a, 3 * i + c, b[i].m[a][c]);
  blocks.setFromTriplets(trip.begin(), trip.end());
  return blocks * dq;
}

namespace {

// BiCGSTAB's relative residual. Against 1e-12 it saves a quarter of the iterations (47
// against 65 at level 4) and moves a level-4 capsule's D at Ca 0.05 by 2e-10 relative,
// a millionth of the time error at the default time.tolerance; 1e-7 saves no more.
constexpr double kSolveTolerance = 1e-9;

// The inverses of the 3 x 3 diagonal blocks of w, as a block-diagonal matrix.
Eigen::SparseMatrix<double>
inverse_diagonal_blocks(const Eigen::SparseMatrix<double>& w) {
  const int n = int(w.rows()) / 3;
  std::vector<Eigen::Matrix3d> block(n, Eigen::Matrix3d::Zero());
  for (int k = 0; k < w.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(w, k); it; ++it)
      if (it.row() / 3 == it.col() / 3)
        block[it.row() / 3](it.row() % 3, it.col() % 3) = it.value();
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(9 * n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d inv = block[i].inverse();
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        trip.emplace_back(3 * i + a, 3 * i + c, inv(a, c));
  }
  Eigen::SparseMatrix<double> d(w.rows(), w.cols());
  d.setFromTriplets(trip.begin(), trip.end());
  return d;
}

} // namespace

// With several capsules the threads share the capsules; one capsule's matrix is built by
// all of them (self_mobility_blocks, Membrane::load_jacobian).
void StiffMembrane::prepare(const std::vector<Vec3>& x, double gamma_dt) {
  const int nn = membrane_.topology().num_nodes;
#pragma omp parallel for schedule(dynamic) if (num_capsules_ > 1)
  for (int c = 0; c < num_capsules_; ++c) {
    auto system = std::make_unique<System>();
    // With the elements' convex part: a compressed element's growing modes stay explicit.
    Matrix w = -gamma_dt * jacobian(&x[c * nn]);
    for (int k = 0; k < 3 * nn; ++k)
      w.coeffRef(k, k) += 1.0;
    // Scaled by its own 3 x 3 diagonal blocks, W needs a quarter fewer iterations than
    // with Eigen's scalar diagonal preconditioner.
    system->scale = inverse_diagonal_blocks(w);
    system->w = system->scale * w;
    system->w.makeCompressed();
    system->iterative.setTolerance(kSolveTolerance);
    system->iterative.compute(system->w);
    systems_[c] = std::move(system);
  }
}

void StiffMembrane::solve(std::vector<Vec3>& v) {
  const int nn = membrane_.topology().num_nodes;
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < num_capsules_; ++c) {
    Eigen::Map<Eigen::VectorXd> vc(&v[c * nn].x, 3 * nn);
    System& s = *systems_[c];
    const Eigen::VectorXd rhs = s.scale * vc;
    Eigen::VectorXd sol = s.iterative.solveWithGuess(rhs, vc); // W is I + O(dt)
    if (s.iterative.info() != Eigen::Success) {
      Eigen::SparseLU<Matrix> lu(s.w);
      if (lu.info() != Eigen::Success)
        throw std::runtime_error("the implicit step's matrix of capsule " +
                                 std::to_string(c) + " is singular");
      sol = lu.solve(rhs);
    }
    vc = sol;
  }
}

} // namespace capsim
