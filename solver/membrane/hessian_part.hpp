#pragma once
// Which Hessian of an element's energy an implicit step linearises with: the exact one,
// or its positive semidefinite part in the edge coordinates (neo_hookean_hessian.hpp's
// positive_part; exact where the element is convex, as everywhere on a stretched
// membrane). Its own header so that the assembly's interface (membrane_forces.hpp,
// included by every flow) does not carry the element Hessians and Eigen's eigensolver:
// those cost about 8 s of compiling in each file that includes them.

namespace capsim {

enum class HessianPart { exact, positive };

} // namespace capsim
