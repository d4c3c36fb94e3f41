# The solver is built by the project's set-up script when it is missing.
rule build_capsim:
    output:
        CAPSIM,
    log:
        "results/logs/build.log",
    params:
        # A parameter, not an input: editing the script does not rebuild the solver.
        setup=os.path.join(ROOT, "scripts", "setup.sh"),
    shell:
        "bash {params.setup} > {log} 2>&1"
