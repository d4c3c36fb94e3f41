"""The whole workflow on the ci configuration (config/ci.yaml), end to end: every study,
figure and table into a temporary working directory, then the `check` target (the
ci_workflow fixture of conftest.py, which test_slurm.py reads too). About 1.5 minutes on
2 cores. Skipped when build/capsim or snakemake is missing."""

import shutil

import pytest
import yaml

from conftest import CAPSIM, ROOT, SNAKEMAKE
from conftest import run_snakemake as snakemake

pytestmark = [
    pytest.mark.skipif(not CAPSIM.exists(), reason="build/capsim is missing (bash scripts/setup.sh)"),
    pytest.mark.skipif(not SNAKEMAKE.exists() and not shutil.which("snakemake"),
                       reason="snakemake is not installed"),
]


def test_ci_workflow_and_check(ci_workflow, tmp_path):
    workdir, proc = ci_workflow
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    figures = workdir / "results" / "figures"
    for n in range(1, 13):
        for ext in ("png", "pdf", "csv"):
            assert (figures / f"fig{n:02d}.{ext}").stat().st_size > 0
    assert (figures / "table1.md").exists() and (figures / "table1.csv").exists()
    # The paper's numbers against the ci run: most are not in this tiny configuration.
    comparison = (figures / "paper_comparison.md").read_text()
    assert "this run (config/ci.yaml)" in comparison
    assert "not in this configuration" in comparison
    assert "Rule (analysis/paper_comparison.py)" in comparison
    # The check held the figure data and the verdicts against config/expected/ci/.
    assert "the paper comparison is as committed; the figure data are as committed" in \
        (workdir / "results" / "check" / "report.md").read_text()
    assert (figures / "paper_comparison.csv").stat().st_size > 0
    # A run two studies need is made once: the mesh study's coarse run and the box-size
    # study's M = 2, seed 1 are the grid's point (Ca 0.4, phi 0.2, M 2, level 1, seed 1);
    # the initial-position runs (t_end 0.4, not 0.3) are their own.
    results = workdir / "results"
    shared = "ca0.4_phi0.2_M2_level1_seed1"
    assert (results / "grid" / shared / "summary.json").exists()
    assert not (results / "mesh" / shared).exists()
    assert not (results / "boxsize" / shared).exists()
    assert (results / "initial" / shared / "summary.json").exists()
    assert f"grid/{shared}" in (results / "mesh" / "table.csv").read_text()
    report = (workdir / "results" / "check" / "report.md").read_text()
    assert "0 failed" in report
    # Nothing is left to do: a second invocation runs no job.
    again = snakemake(workdir, "all", "check", "-n")
    assert again.returncode == 0
    assert "Nothing to be done" in again.stdout + again.stderr
    assert "main studies: 0 of 16 runs to compute, about 0.0 h" in again.stderr
    # A seed added to a study's list is seen where its table exists: the configuration
    # files are an input of every table (modification times alone would not see it).
    more = yaml.safe_load((ROOT / "config" / "ci.yaml").read_text())
    more["initial"]["seeds"] = [1, 2, 3]
    (tmp_path / "more.yaml").write_text(yaml.safe_dump(more))
    plan = snakemake(workdir, "all", "-n", extra=["--configfile", str(tmp_path / "more.yaml")])
    assert plan.returncode == 0, plan.stdout[-3000:] + plan.stderr[-3000:]
    jobs = planned_jobs(plan.stdout)
    assert jobs["run"] == 1 and jobs["run_table"] >= 1
    assert "results/initial/ca0.4_phi0.2_M2_level1_seed3" in plan.stdout


def planned_jobs(output):
    """{rule: count} of a dry run's job table."""
    words = [line.split() for line in output.splitlines()]
    return {w[0]: int(w[1]) for w in words if len(w) == 2 and w[1].isdigit()}


# Every configuration validates against the schema and plans its jobs from scratch (no
# archive); the counts are those each configuration's header and docs/workflow.md state
# (runs that two studies share counted once: suspensions + dilute runs), and the runs of
# the studies on the page that are not main studies (on_page: reference).
@pytest.mark.parametrize("configfile, runs, on_page", [
    ("config.yaml", 40 + 21, 0),
    # 44: the mesh study's level 3 is the grid's run (both to t_e 30); 22: the limit
    # eb -> 0 (eblimit.in_grid); 3: the reference study's seeds (reference.on_page)
    ("quantitative.yaml", 44 + 21 + 22, 3),
])
def test_configuration_plans(tmp_path, configfile, runs, on_page):
    (tmp_path / "no_archive.yaml").write_text("archive: null\n")
    proc = snakemake(tmp_path, "all", "check", "-n", configfile=configfile,
                     extra=[str(tmp_path / "no_archive.yaml")])
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert planned_jobs(proc.stdout)["run"] == runs + on_page
    # The estimate counts the runs the plan has (the main studies' runs, each once).
    assert f"main studies: {runs} of {runs} runs to compute" in proc.stderr
