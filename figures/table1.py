"""Table 1 (analysis.table1): the workflow's entry beside the figure scripts.

Usage: python figures/table1.py --out results/figures/table1 results/mesh/table.csv
"""

from analysis.table1 import main

if __name__ == "__main__":
    main()
