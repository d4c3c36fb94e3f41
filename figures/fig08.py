"""Figure 8: ratios of (a) b1 phi and (b) b1 phi + b2 phi^2 to N1 against phi for each Ca;
1 - (b) is the O(phi^3) share of N1. Bars: standard errors propagated from those of the
time averages.

Usage: python figures/fig08.py --out results/figures/fig08 results/grid/table.csv
       results/grid/fits.csv
"""

import common
from fig06 import share_figure

if __name__ == "__main__":
    share_figure(common.parse_args(__doc__.splitlines()[0]), "N1",
                 (r"$b_1\phi/N_1$", r"$(b_1\phi + b_2\phi^2)/N_1$"), 8, rigid=False)
