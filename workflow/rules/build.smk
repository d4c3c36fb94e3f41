# The solver is built by the project's set-up script when it is missing.
rule build_capsim:
    output:
        CAPSIM,
    log:
        "results/logs/build.log",
    shell:
        "bash {ROOT}/scripts/setup.sh > {log} 2>&1"
