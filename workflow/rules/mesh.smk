# Mesh convergence (Table 1): Ca, phi, M fixed; N_E = 20 * 4^level for every level of
# config["mesh"]["mesh_levels"]; the finest level with every seed (the reference is their
# mean, as the paper's three initial positions at N_E = 5120), the others with the first.
# mesh.membranes: the levels whose runs carry another membrane code (analysis/membrane.py),
# e.g. rep5 where the capsules of a coarse mesh come into contact at run_options'
# repulsion; checked here, before any run.
MESH = config["mesh"]
MESH_MEMBRANES = {int(entry["mesh_level"]): membrane_codes.canonical(entry["membrane"],
                                                                   "mesh.membranes")
                  for entry in MESH.get("membranes", [])}


def mesh_keys():
    finest = max(MESH["mesh_levels"])
    return [dict(ca=MESH["ca"], phi=MESH["phi"], M=MESH["capsules"], level=level, seed=seed,
                 membrane=MESH_MEMBRANES.get(level, membrane_codes.PAPER))
            for level in MESH["mesh_levels"]
            for seed in (MESH["seeds"] if level == finest else MESH["seeds"][:1])]


STUDY_KEYS["mesh"] = mesh_keys
