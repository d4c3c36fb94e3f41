#pragma once
// The stiff part of the node velocities' Jacobian that the implicit (IMEX) step inverts:
// each capsule's own elastic load acting through its own single layer, reduced to the
// nodes' self-mobility blocks, J_c = B dq/dx (stokes/kernels/self_mobility.hpp,
// Membrane::load_jacobian). It is what limits an explicit step to dt ~ Ca h: the
// element-scale modes relax at ~ 1/(Ca h) through the singular self-interaction, while
// the far field of the capsule, the other capsules and the shear change on the flow's
// time scale. A block-diagonal B keeps W = I - gamma dt J sparse and positive enough;
// a banded truncation of the single layer (one or two rings of neighbours) is not.
#include "common/block_rows.hpp"
#include "common/fixed_pattern.hpp"
#include "membrane/membrane_forces.hpp"
#include "stokes/single_layer/single_layer.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <memory>
#include <mutex>
#include <vector>

namespace capsim {

class StiffMembrane {
public:
  StiffMembrane(const Membrane& membrane, int num_capsules, QuadratureOptions quadrature);

  // Builds W_c = I - gamma_dt J_c of every capsule at positions x.
  void prepare(const std::vector<Vec3>& x, double gamma_dt);
  // v <- W^-1 v, capsule by capsule: BiCGSTAB on W scaled by its inverse 3 x 3 diagonal
  // blocks, to a relative residual of 1e-9 (a few milliseconds at 642 nodes, where a
  // sparse LU costs 5-20 times more), a sparse LU where that does not converge.
  void solve(std::vector<Vec3>& v);

  // J_c of capsule c at its positions xc (3N x 3N), with the elements' convex part (what
  // prepare() uses) or, for tests and diagnostics, their exact Hessians.
  Eigen::SparseMatrix<double> jacobian(const Vec3* xc,
                                       HessianPart part = HessianPart::positive) const;

private:
  // J_c as jacobian() builds it, by 3 x 3 block rows.
  BlockRows jacobian_blocks(const Vec3* xc,
                            HessianPart part = HessianPart::positive) const;

  struct System {
    std::vector<Eigen::Matrix3d> scale; // the inverse diagonal blocks of W
    BlockRows w;                        // scale * W
    Eigen::BiCGSTAB<BlockRows, Eigen::IdentityPreconditioner> iterative; // refers to w
  };
  const Membrane& membrane_;
  int num_capsules_;
  QuadratureOptions quadrature_;
  std::vector<std::unique_ptr<System>> systems_;
  // dq/dx's pattern depends only on the mesh: learnt from the first J built.
  mutable std::once_flag pattern_once_;
  mutable std::unique_ptr<FixedPatternAssembly> load_jacobian_assembly_;
};

} // namespace capsim
