#include "dynamics/stiff_membrane.hpp"

#include "stokes/kernels/self_mobility.hpp"

#include <Eigen/LU>
#include <Eigen/SparseLU>
#include <stdexcept>

namespace capsim {

StiffMembrane::StiffMembrane(const Membrane& membrane, int num_capsules,
                             QuadratureOptions quadrature)
    : membrane_(membrane), num_capsules_(num_capsules), quadrature_(quadrature),
      systems_(num_capsules) {}

namespace {

// BiCGSTAB's relative residual. Against 1e-12 it saves a quarter of the iterations (47
// against 65 at level 4) and moves a level-4 capsule's D at Ca 0.05 by 2e-10 relative,
// a millionth of the time error at the default time.tolerance; 1e-7 saves no more.
constexpr double kSolveTolerance = 1e-9;

// The inverses of the 3 x 3 blocks b.
std::vector<Eigen::Matrix3d> inverses(std::vector<Eigen::Matrix3d> b) {
  for (Eigen::Matrix3d& m : b)
    m = m.inverse().eval();
  return b;
}

} // namespace

BlockRows StiffMembrane::jacobian_blocks(const Vec3* xc, HessianPart part) const {
  const Topology& topo = membrane_.topology();
  std::vector<Vec3> grad;
  membrane_.energy_gradient(xc, grad);
  const auto trip = membrane_.load_jacobian_triplets(xc, grad, part);
  std::call_once(pattern_once_, [&] {
    load_jacobian_assembly_ = std::make_unique<FixedPatternAssembly>(
        3 * topo.num_nodes, 3 * topo.num_nodes, trip);
  });
  BlockRows j(load_jacobian_assembly_->assemble(trip)); // dq/dx
  // Row block i of B dq/dx is B_i times row block i of dq/dx.
  const std::vector<Mat3> b = self_mobility_blocks(topo, xc, quadrature_);
  std::vector<Eigen::Matrix3d> left(b.size());
  for (size_t i = 0; i < b.size(); ++i)
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        left[i](a, c) = b[i].m[a][c];
  j.multiply_rows(left);
  return j;
}

Eigen::SparseMatrix<double> StiffMembrane::jacobian(const Vec3* xc,
                                                    HessianPart part) const {
  return jacobian_blocks(xc, part).to_sparse();
}

// With several capsules the threads share the capsules; one capsule's matrix is built by
// all of them (self_mobility_blocks, Membrane::load_jacobian).
void StiffMembrane::prepare(const std::vector<Vec3>& x, double gamma_dt) {
  const int nn = membrane_.topology().num_nodes;
#pragma omp parallel for schedule(dynamic) if (num_capsules_ > 1)
  for (int c = 0; c < num_capsules_; ++c) {
    auto system = std::make_unique<System>();
    // With the elements' convex part: a compressed element's growing modes stay explicit.
    system->w = jacobian_blocks(&x[c * nn]);
    system->w.scale_and_add_identity(-gamma_dt);
    // Scaled by its own 3 x 3 diagonal blocks, W needs a quarter fewer iterations than
    // with Eigen's scalar diagonal preconditioner.
    system->scale = inverses(system->w.diagonal_blocks());
    system->w.multiply_rows(system->scale);
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
    Eigen::VectorXd rhs(3 * nn);
    for (int i = 0; i < nn; ++i)
      rhs.segment<3>(3 * i) = s.scale[i] * vc.segment<3>(3 * i);
    Eigen::VectorXd sol = s.iterative.solveWithGuess(rhs, vc); // W is I + O(dt)
    if (s.iterative.info() != Eigen::Success) {
      Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(s.w.to_sparse());
      if (lu.info() != Eigen::Success)
        throw std::runtime_error("the implicit step's matrix of capsule " +
                                 std::to_string(c) + " is singular");
      sol = lu.solve(rhs);
    }
    vc = sol;
  }
}

} // namespace capsim
