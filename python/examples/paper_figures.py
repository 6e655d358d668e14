"""Two figures of Pombo, Ambrósio & Silva (VSD 45(2), 2007, §5) from Python.

- Fig. 15: lateral displacement of the unsuspended ML95-like wheelset,
  released 2 mm off centre, at 2, 10, 15 and 20 m/s (Polach): constant
  amplitude at 2 m/s, growing above, flange-limited at 20 m/s; the
  wavelength is Klingel's 15.9 m.
- Fig. 19: lateral contact forces on both wheels of the bogie's front
  wheelset at 20 m/s (Polach): the Y force of EN 14363, + towards the
  track centre, so a centred wheelset's two wheels carry the same
  positive Y (the inward components of their inclined normal forces).

Our ML95-like data are not the paper's (docs/guide/critical-speed.md), so
the curves agree in kind, not in every number.

    python python/examples/paper_figures.py [--out DIR]

writes fig15_wheelset_lateral.png and fig19_bogie_lateral_forces.png.
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import railsim  # noqa: E402

SCENES = pathlib.Path(__file__).resolve().parents[2] / "tables" / "scenes"


def fig15(out):
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for speed in (2, 10, 15, 20):
        r = railsim.run(
            SCENES / "wheelset_straight.toml",
            set={"initial.speed_m_s": speed, "run.distance_m": 100},
            progress=False,
        )
        ax.plot(r["wheelset_0/distance_m"], 1e3 * r["wheelset_0/lateral_m"], label=f"{speed} m/s")
        print(f"wheelset at {speed:>2} m/s: RTF {r.summary['real_time_factor']:.1f}, "
              f"peak {r.summary['wheelsets'][0]['peak_lateral_mm']:.2f} mm")
    ax.set_xlabel("distance travelled (m)")
    ax.set_ylabel("lateral displacement, + left (mm)")
    ax.set_title("ML95-like wheelset, 2 mm initial offset, Polach (paper Fig. 15)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    path = out / "fig15_wheelset_lateral.png"
    fig.savefig(path, dpi=110, bbox_inches="tight")
    return path


def fig19(out):
    r = railsim.run(SCENES / "bogie_straight.toml", set={"initial.speed_m_s": 20}, progress=False)
    t = r.time_s
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for side in ("left", "right"):
        ax.plot(t, 1e-3 * r[f"wheelset_0/{side}/y_n"], label=f"{side} wheel")
    print(f"bogie at 20 m/s: RTF {r.summary['real_time_factor']:.1f}, "
          f"{r.summary['steps']} steps")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("lateral force Y on the wheel,\n+ towards the track centre (kN)")
    ax.set_xlim(0.0, 5.0)
    ax.set_title("ML95-like bogie, front wheelset, 20 m/s, Polach (paper Fig. 19)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    path = out / "fig19_bogie_lateral_forces.png"
    fig.savefig(path, dpi=110, bbox_inches="tight")
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("paper_figures"))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for path in (fig15(args.out), fig19(args.out)):
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
