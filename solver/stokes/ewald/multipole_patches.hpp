#pragma once
// Multipole-patch coarse graining of the single layer (paper section 3.1, eqs. 3.3-3.12):
// the capsule surface is split into P patches, the faces of a coarser icosphere level
// (P = 20 * 4^l), or one patch (P = 1); far from a patch its load acts through the force
// F = int q dA (eq. 3.4) and the first moment D_jk = int q_j (y - c)_k dA about the patch
// centre c, whose antisymmetric part is the torque L (eq. 3.5) and whose symmetric
// traceless part is the stresslet S (eq. 3.6).
#include "mesh/icosphere.hpp"

#include <vector>

namespace capsim {

struct PatchMoments {
  Vec3 centre; // area centroid of the patch
  Vec3 force;  // F
  Mat3 dipole; // D_jk = int q_j (y - c)_k dA
};

// Patches of one capsule meshed at mesh_level; patch_level < 0 gives one patch (P = 1),
// otherwise P = 20 * 4^patch_level (patch_level <= mesh_level). x, q: the capsule's
// nodes.
std::vector<PatchMoments> patch_moments(const Topology& topo, int mesh_level,
                                        int patch_level, const Vec3* x, const Vec3* q);

// sum_p J(x - c_p) F_p - d_k J(x - c_p) D_p (eq. 3.10 without the -1/(8 pi mu) factor).
Vec3 patch_velocity(Vec3 x, const std::vector<PatchMoments>& patches);

// The accurate single layer int J(x - y) q dA at an off-surface point (eq. 3.9 without
// the factor): every triangle by adaptive quadrature.
Vec3 surface_velocity_at(Vec3 x, const Topology& topo, const Vec3* nodes, const Vec3* q);

} // namespace capsim
