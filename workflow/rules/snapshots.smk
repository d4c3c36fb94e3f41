# Snapshots (figure 2): one run per phi at one Ca, writing mesh snapshots of the box;
# the figure draws the last one with its periodic images.
SNAPSHOTS = config["snapshots"]


def snapshot_keys():
    return [dict(ca=SNAPSHOTS["ca"], phi=phi, M=SNAPSHOTS["capsules"],
                 level=SNAPSHOTS["mesh_level"], seed=SNAPSHOTS["seed"])
            for phi in SNAPSHOTS["phi"]]


STUDY_KEYS["snapshots"] = snapshot_keys
