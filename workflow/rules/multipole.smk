# Multipole error (figure 1): for each Ca, the capsule of the dilute run at the configured
# mesh level; `capsim multipole-error` writes the relative error of the P-patch expansion
# (eq. 3.11) at distances r/a along the flow, vorticity and gradient directions.
# The tables figure 1 reads: multipole_tables() (common.smk), one per dilute run of
# multipole_runs(), named as its run folder (each names its Ca and level in its columns).
MULTIPOLE = config["multipole"]
DILUTE_KEYS.append(lambda: [(ca, MULTIPOLE["mesh_level"]) for ca in MULTIPOLE["ca"]])


rule multipole_error:
    input:
        capsim=ancient(CAPSIM),
        run=lambda wc: os.path.join(multipole_runs()[wc.run].folder, "summary.json"),
    output:
        "results/multipole/{run}.csv",
    log:
        "results/logs/multipole/{run}.log",
    params:
        dir=lambda wc: multipole_runs()[wc.run].folder,
        patches=" ".join(str(p) for p in MULTIPOLE["patches"]),
        distances=" ".join(str(r) for r in MULTIPOLE["distances"]),
    shell:
        "{input.capsim} multipole-error {params.dir} --patches {params.patches} "
        "--distances {params.distances} -o {output} > {log} 2>&1"
