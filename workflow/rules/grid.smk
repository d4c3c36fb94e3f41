# The main study (figures 3-10): every Ca x phi of config["grid"], with M capsules at one
# mesh level and seed; phi = 0 is the dilute limit at the same Ca and mesh level.
# Output: results/grid/table.csv, one row of averages per run (dilute rows included).
GRID = config["grid"]


# grid.membranes: the points that carry another membrane than the paper's (where it
# folds, docs/suspensions.md), each {ca, phi, membrane: code}; checked here, before any
# run, by analysis.membrane.point_membranes.
GRID_MEMBRANES = membrane_codes.point_membranes(
    GRID.get("membranes", []), GRID["ca"], GRID["phi"], "grid.membranes")


# grid.t_end_at: the points that run longer than grid.t_end ({ca, phi, t_end}: for the
# precision of the O(phi^3) shares, docs/workflow.md); pipeline.run_spec.suspension gives
# each its own t_end (in every study that runs it: eblimit's runs of the point too);
# checked here, before any run.
run_spec.point_t_ends(GRID, "grid.t_end_at")


def grid_keys():
    return [dict(ca=ca, phi=phi, M=GRID["capsules"], level=GRID["mesh_level"], seed=seed,
                 membrane=GRID_MEMBRANES.get((float(ca), float(phi)), membrane_codes.PAPER))
            for ca in GRID["ca"] for phi in GRID["phi"] for seed in GRID["seeds"]]


def grid_dilute():
    return [dilute_summary(ca, GRID["mesh_level"]) for ca in GRID["ca"]]


STUDY_KEYS["grid"] = grid_keys
STUDY_DILUTE["grid"] = grid_dilute
DILUTE_KEYS.append(lambda: [(ca, GRID["mesh_level"]) for ca in GRID["ca"]])
