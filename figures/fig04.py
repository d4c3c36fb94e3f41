"""Figure 4: (a) ensemble average of the orientation angle <theta_D> (degrees) and its slope,
(b) its standard deviation sigma_theta, against phi for each Ca, with standard errors.

Usage: python figures/fig04.py --out results/figures/fig04 results/grid/table.csv
"""

import common
from fig03 import panels

if __name__ == "__main__":
    panels(common.parse_args(__doc__.splitlines()[0]), "theta_D_deg", "theta_D_se_deg",
           "theta_D_std_deg", "theta_D_std_se_deg", r"$\langle\theta_D\rangle$ (deg)",
           r"$\sigma_{\theta_D}$ (deg)", 4)
