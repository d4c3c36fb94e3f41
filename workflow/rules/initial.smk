# Initial positions and end time (figure 11): one (Ca, phi, M, level), several seeds, run
# to t_end; the figure plots the averages from t_s over [t_s, t_e] against t_e.
INITIAL = config["initial"]


def initial_keys():
    return [dict(ca=INITIAL["ca"], phi=INITIAL["phi"], M=INITIAL["capsules"],
                 level=INITIAL["mesh_level"], seed=seed)
            for seed in INITIAL["seeds"]]


STUDY_KEYS["initial"] = initial_keys
