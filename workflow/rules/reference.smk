# The paper's scale at its reference point (Table 1's case, Ca 0.2, phi 0.3): M capsules
# to gammadot t_e of config["reference"] (the paper: M = 100 to t_e = 100), one run per
# seed, with the block's own capsim options after the configuration's run_options (the
# time scheme and precisions that meet the workflow's error rule at less cost). Optional:
# a configuration without the block has no such runs. Run by its own target,
# `snakemake reference`, not by `all`: its runs take hours on 2 cores and are computed
# and archived first; results/reference/table.csv holds their averages. `on_page: true`
# (set it once its runs are in the archive) puts them in the comparison with the paper
# and on the results page, whose rules then need them (restored from the archive).
REFERENCE = config.get("reference")
REFERENCE_PAGE = ["results/reference/table.csv"] if REFERENCE and REFERENCE.get("on_page") \
    else []


def reference_keys():
    if not REFERENCE:
        return []
    return [dict(ca=REFERENCE["ca"], phi=REFERENCE["phi"], M=REFERENCE["capsules"],
                 level=REFERENCE["mesh_level"], seed=seed)
            for seed in REFERENCE["seeds"]]


STUDY_KEYS["reference"] = reference_keys
ON_DEMAND_RUNS["reference"] = lambda: [run_owner("reference", **k) for k in reference_keys()]


rule reference:
    input:
        "results/reference/table.csv" if REFERENCE else [],
