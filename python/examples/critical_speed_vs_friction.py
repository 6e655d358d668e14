"""A small parameter study from Python: the critical speed of the
ML95-like bogie against the coefficient of friction, for three creep laws
(time-domain method: bisection on the growth rate of the hunting motion).

    python python/examples/critical_speed_vs_friction.py [--out DIR]

prints a table and writes critical_speed_vs_friction.png (and .csv).
"""

import argparse
import csv
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import railsim  # noqa: E402

SCENE = pathlib.Path(__file__).resolve().parents[2] / "tables" / "scenes" / "bogie_straight.toml"
FRICTION = [0.1, 0.2, 0.3, 0.4]
LAWS = ["kalker", "heuristic", "polach"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("critical_speed_study"))
    parser.add_argument("--tol-m-s", type=float, default=0.5, help="bracket width (m/s)")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for mu in FRICTION:
        found = railsim.critical_speed(
            SCENE, creep=LAWS, method=["time"], min_m_s=10.0, max_m_s=120.0,
            tol_m_s=args.tol_m_s, set={"contact.friction": mu},
        )
        for r in found:
            rows.append({"friction": mu, "creep_law": r["creep_law"], "speed_m_s": r["speed_m_s"]})
            speed = "none found" if r["speed_m_s"] is None else f"{r['speed_m_s']:6.1f} m/s"
            print(f"mu = {mu:.2f}  {r['creep_law']:<9}  critical speed {speed}")
    with open(args.out / "critical_speed_vs_friction.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["friction", "creep_law", "speed_m_s"])
        w.writeheader()
        w.writerows(rows)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for law in LAWS:
        pts = [(r["friction"], r["speed_m_s"]) for r in rows
               if r["creep_law"] == law and r["speed_m_s"] is not None]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=law)
    ax.set_xlabel("coefficient of friction μ (–)")
    ax.set_ylabel("critical speed (m/s)")
    ax.set_title("ML95-like bogie: critical speed against friction (time domain)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    path = args.out / "critical_speed_vs_friction.png"
    fig.savefig(path, dpi=110, bbox_inches="tight")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
