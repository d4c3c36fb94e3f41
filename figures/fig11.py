"""Figure 11: effect of the end time t_e on (a) the ensemble average <D> and (b) mu_sp,
averaged from t_s, for several initial positions (seeds); the text gives the mean and
standard deviation of the cases at the last t_e.

Usage: python figures/fig11.py --out results/figures/fig11 [--t-start 10] RUN/summary.json ...
"""

from pathlib import Path

import common
from analysis.averages import ensemble, running_average
from analysis.read_run import read_summary, read_timeseries
from analysis.rheology import stress_factor


def main(args):
    fig, (ax_a, ax_b) = common.plt.subplots(1, 2, figsize=(7.0, 3.0))
    data, finals, meta = [], {"D": [], "mu_sp": []}, []
    for path in args.inputs:
        run = Path(path).parent if path.endswith(".json") else Path(path)
        p = read_summary(run)["parameters"]
        ts = read_timeseries(run)
        t_ends = ts["time"][ts["time"] > args.t_start]
        if t_ends.size == 0:
            raise SystemExit(f"fig11: {run} ends at {ts['time'][-1]}, before t_s = {args.t_start}")
        factor = stress_factor(float(p["phi"]), float(p["ca"]))  # mu_sp from S_xy, eq. 4.5
        d = running_average(ts["D"], ts["time"], args.t_start, t_ends)
        mu = factor * running_average(ts["stresslet"][:, :, 0, 1], ts["time"], args.t_start, t_ends)
        seed = int(p["seed"])
        ax_a.plot(t_ends, d, label=f"seed {seed}")
        ax_b.plot(t_ends, mu, label=f"seed {seed}")
        data += [{"seed": seed, "t_e": t, "D": a, "mu_sp": b} for t, a, b in zip(t_ends, d, mu)]
        finals["D"].append(d[-1])
        finals["mu_sp"].append(mu[-1])
        meta.append(p)
    for ax, key, label in ((ax_a, "D", r"$\langle D\rangle$"), (ax_b, "mu_sp", r"$\mu_{sp}$")):
        mean, std = ensemble(finals[key])
        ax.text(0.95, 0.05, f"{mean:.4f} $\\pm$ {std:.4f}", transform=ax.transAxes,
                ha="right", va="bottom")
        ax.set(xlabel=r"$\dot\gamma t_e$", ylabel=label)
        data.append({"seed": "mean", "t_e": max(r["t_e"] for r in data), key: mean,
                     key + "_std": std, "cases": len(finals[key])})
    ax_a.set_title("(a)")
    ax_b.set_title("(b)")
    ax_a.legend()
    fig.tight_layout()
    p = meta[0]
    caption = (f"Figure 11. Averages from gammadot t_s = {args.t_start:g} to t_e for "
               f"{len(meta)} initial positions; Ca = {float(p['ca']):g}, phi = "
               f"{float(p['phi']):g}; mean +- standard deviation of the cases at the last t_e. "
               f"Runs: N_E = {common.elements(p['mesh_level'])}; M = {int(p['capsules'])}; "
               f"gammadot t_e up to {max(r['t_e'] for r in data):.3g}.")
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    main(common.parse_args(__doc__.splitlines()[0]))
