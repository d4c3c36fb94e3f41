"""Figure 11: effect of the end time t_e on (a) the ensemble average <D> and (b) mu_sp,
averaged from t_s, for several initial positions (seeds), each with a band of +- the
standard error of its running average; the text gives the mean and standard deviation of
the cases at the last t_e and the standard error of that mean.

Usage: python figures/fig11.py --out results/figures/fig11 [--t-start 10] RUN/summary.json ...
"""

from pathlib import Path

import common
from analysis.averages import ensemble, running_average, running_standard_error
from analysis.read_run import read_summary, read_timeseries
from analysis.rheology import stress_factor
from analysis.statistics import mean_of_runs_standard_error


def main(args):
    fig, (ax_a, ax_b) = common.plt.subplots(1, 2, figsize=(7.0, 3.0))
    data, meta = [], []
    finals = {"D": [], "mu_sp": [], "D_se": [], "mu_sp_se": []}
    for path in args.inputs:
        run = Path(path).parent if path.endswith(".json") else Path(path)
        p = read_summary(run)["parameters"]
        ts = read_timeseries(run)
        t_ends = ts["time"][ts["time"] > args.t_start]
        if t_ends.size == 0:
            raise SystemExit(f"fig11: {run} ends at {ts['time'][-1]}, before t_s = {args.t_start}")
        factor = stress_factor(float(p["phi"]), float(p["ca"]))  # mu_sp from S_xy, eq. 4.5
        s_xy = ts["stresslet"][:, :, 0, 1]
        series = {"D": running_average(ts["D"], ts["time"], args.t_start, t_ends),
                  "D_se": running_standard_error(ts["D"], ts["time"], args.t_start, t_ends),
                  "mu_sp": factor * running_average(s_xy, ts["time"], args.t_start, t_ends),
                  "mu_sp_se": factor * running_standard_error(s_xy, ts["time"], args.t_start,
                                                              t_ends)}
        seed = int(p["seed"])
        for ax, key in ((ax_a, "D"), (ax_b, "mu_sp")):
            y, se = series[key], series[key + "_se"]
            (line,) = ax.plot(t_ends, y, label=f"seed {seed}")
            ax.fill_between(t_ends, y - se, y + se, color=line.get_color(), alpha=0.25, lw=0)
        data += [{"seed": seed, "t_e": t, **{k: v[i] for k, v in series.items()}}
                 for i, t in enumerate(t_ends)]
        for key, values in series.items():
            finals[key].append(values[-1])
        meta.append(p)
    for ax, key, label in ((ax_a, "D", r"$\langle D\rangle$"), (ax_b, "mu_sp", r"$\mu_{sp}$")):
        mean, std = ensemble(finals[key])
        se = mean_of_runs_standard_error(finals[key + "_se"])
        ax.text(0.95, 0.05, f"{mean:.4f} $\\pm$ {std:.4f} (SE {se:.2g})",
                transform=ax.transAxes, ha="right", va="bottom")
        ax.set(xlabel=r"$\dot\gamma t_e$", ylabel=label)
        data.append({"seed": "mean", "t_e": max(r["t_e"] for r in data), key: mean,
                     key + "_std": std, key + "_se": se, "cases": len(finals[key])})
    ax_a.set_title("(a)")
    ax_b.set_title("(b)")
    ax_a.legend()
    fig.tight_layout()
    p = meta[0]
    caption = (f"Figure 11. Averages from gammadot t_s = {args.t_start:g} to t_e for "
               f"{len(meta)} initial positions; Ca = {float(p['ca']):g}, phi = "
               f"{float(p['phi']):g}. Bands: +- the standard error of each running average "
               "at t_e, from the integrated autocorrelation time (docs/conventions.md; "
               "rough near t_s, where the window holds few correlation times). Text: mean "
               "+- standard deviation of the cases at the last t_e (the paper's measure), "
               "and the standard error of that mean, sqrt(sum se_i^2) / n. "
               f"Runs: N_E = {common.elements(p['mesh_level'])}; M = {int(p['capsules'])}; "
               f"gammadot t_e up to {max(r['t_e'] for r in data):.3g}.")
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    main(common.parse_args(__doc__.splitlines()[0]))
