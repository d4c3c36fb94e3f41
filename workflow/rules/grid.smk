# The main study (figures 3-10): every Ca x phi of config["grid"], with M capsules at one
# mesh level and seed; phi = 0 is the dilute limit at the same Ca and mesh level.
# Output: results/grid/table.csv, one row of averages per run (dilute rows included).
GRID = config["grid"]


def grid_keys():
    return [dict(ca=ca, phi=phi, M=GRID["capsules"], level=GRID["mesh_level"], seed=seed)
            for ca in GRID["ca"] for phi in GRID["phi"] for seed in GRID["seeds"]]


def grid_dilute():
    return [dilute_summary(ca, GRID["mesh_level"]) for ca in GRID["ca"]]


STUDY_KEYS["grid"] = grid_keys
STUDY_DILUTE["grid"] = grid_dilute
