# Capsules per box (figure 12): one (Ca, phi, level), every M of config["boxsize"], each
# with every seed; the figure shows the mean and standard deviation over the seeds.
BOXSIZE = config["boxsize"]


def boxsize_keys():
    return [dict(ca=BOXSIZE["ca"], phi=BOXSIZE["phi"], M=m, level=BOXSIZE["mesh_level"],
                 seed=seed)
            for m in BOXSIZE["capsules"] for seed in BOXSIZE["seeds"]]


STUDY_KEYS["boxsize"] = boxsize_keys
