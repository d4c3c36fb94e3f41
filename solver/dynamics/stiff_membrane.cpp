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

namespace {

// BiCGSTAB's relative residual. Against 1e-12 it saves a quarter of the iterations (47
// against 65 at level 4) and moves a level-4 capsule's D at Ca 0.05 by 2e-10 relative,
// a millionth of the time error at the default time.tolerance; 1e-7 saves no more.
constexpr double kSolveTolerance = 1e-9;

// Multiplies row block i (rows 3i to 3i + 2) of m by left[i], in place. m holds whole
// 3 x 3 blocks (a node pair's), so in each column the three rows of a block are adjacent;
// this is the product with a block-diagonal matrix without a sparse-sparse product.
void multiply_block_rows(const std::vector<Eigen::Matrix3d>& left,
                         Eigen::SparseMatrix<double>& m) {
  const int* outer = m.outerIndexPtr();
  const int* inner = m.innerIndexPtr();
  for (int k = 0; k < m.outerSize(); ++k)
    for (int p = outer[k]; p < outer[k + 1]; p += 3) {
      if (!starts_block(inner, p, outer[k + 1]))
        throw std::logic_error(
            "multiply_block_rows: the matrix is not made of 3x3 blocks");
      Eigen::Map<Eigen::Vector3d> v(m.valuePtr() + p);
      v = left[inner[p] / 3] * v; // products evaluate into a temporary first
    }
}

// The inverses of the 3 x 3 diagonal blocks of w.
std::vector<Eigen::Matrix3d>
inverse_diagonal_blocks(const Eigen::SparseMatrix<double>& w) {
  std::vector<Eigen::Matrix3d> block(w.rows() / 3, Eigen::Matrix3d::Zero());
  for (int k = 0; k < w.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(w, k); it; ++it)
      if (it.row() / 3 == it.col() / 3)
        block[it.row() / 3](it.row() % 3, it.col() % 3) = it.value();
  for (Eigen::Matrix3d& b : block)
    b = b.inverse().eval();
  return block;
}

} // namespace

Eigen::SparseMatrix<double> StiffMembrane::jacobian(const Vec3* xc,
                                                    HessianPart part) const {
  const Topology& topo = membrane_.topology();
  std::vector<Vec3> grad;
  membrane_.energy_gradient(xc, grad);
  const auto trip = membrane_.load_jacobian_triplets(xc, grad, part);
  std::call_once(pattern_once_, [&] {
    load_jacobian_assembly_ = std::make_unique<FixedPatternAssembly>(
        3 * topo.num_nodes, 3 * topo.num_nodes, trip);
  });
  Matrix j = load_jacobian_assembly_->assemble(trip); // dq/dx
  // Row block i of B dq/dx is B_i times row block i of dq/dx.
  const std::vector<Mat3> b = self_mobility_blocks(topo, xc, quadrature_);
  std::vector<Eigen::Matrix3d> left(b.size());
  for (size_t i = 0; i < b.size(); ++i)
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        left[i](a, c) = b[i].m[a][c];
  multiply_block_rows(left, j);
  return j;
}

// With several capsules the threads share the capsules; one capsule's matrix is built by
// all of them (self_mobility_blocks, Membrane::load_jacobian).
void StiffMembrane::prepare(const std::vector<Vec3>& x, double gamma_dt) {
  const int nn = membrane_.topology().num_nodes;
#pragma omp parallel for schedule(dynamic) if (num_capsules_ > 1)
  for (int c = 0; c < num_capsules_; ++c) {
    auto system = std::make_unique<System>();
    // With the elements' convex part: a compressed element's growing modes stay explicit.
    Matrix w = jacobian(&x[c * nn]);
    w *= -gamma_dt;
    for (int k = 0; k < 3 * nn; ++k)
      w.coeffRef(k, k) += 1.0;
    // Scaled by its own 3 x 3 diagonal blocks, W needs a quarter fewer iterations than
    // with Eigen's scalar diagonal preconditioner.
    system->scale = inverse_diagonal_blocks(w);
    multiply_block_rows(system->scale, w);
    system->w = std::move(w);
    system->blocks = BlockRows(system->w);
    system->iterative.setTolerance(kSolveTolerance);
    system->iterative.compute(system->blocks);
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
