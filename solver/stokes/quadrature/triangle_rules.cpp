#include "stokes/quadrature/triangle_rules.hpp"

#include <cmath>

namespace capsim {
LineRule gauss_legendre_01(int n) {
  LineRule r;
  for (int i = 0; i < n; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = z; // P_0, P_1, then the recurrence up to P_n
      for (int k = 2; k <= n; ++k) {
        double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16)
        break;
    }
    r.x.push_back(0.5 * (1 - z));
    r.w.push_back(1.0 / ((1 - z * z) * dp * dp)); // 2/((1-z^2) P_n'^2), halved for [0,1]
  }
  return r;
}

} // namespace capsim
