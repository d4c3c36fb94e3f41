# Mesh convergence (Table 1): Ca, phi, M fixed; N_E = 20 * 4^level for every level of
# config["mesh"]["mesh_levels"]; the finest level with every seed (the reference is their
# mean, as the paper's three initial positions at N_E = 5120), the others with the first.
MESH = config["mesh"]


def mesh_keys():
    finest = max(MESH["mesh_levels"])
    return [dict(ca=MESH["ca"], phi=MESH["phi"], M=MESH["capsules"], level=level, seed=seed)
            for level in MESH["mesh_levels"]
            for seed in (MESH["seeds"] if level == finest else MESH["seeds"][:1])]


STUDY_KEYS["mesh"] = mesh_keys
