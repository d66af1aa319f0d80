"""Sweep an obstacle's position in the 2D dam break and plot the peak force on it.

The shipped scene scenes/dam_break_2d.toml is read as a dict, a box obstacle is added on the
floor at each position, and each variant runs for a short time at a coarse spacing (well under
a minute in all on two cores). The peak horizontal force on the obstacle against its distance
from the column is written to sweep_obstacle.png (with Matplotlib; without it, printed only).

    python python/examples/sweep_obstacle.py [--out DIR]
"""

import argparse
from pathlib import Path

import numpy as np

import sph

try:
    import tomllib  # Python 3.11+
except ImportError:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
POSITIONS = [0.35, 0.45, 0.55]  # the obstacle's upstream face [m]; the column ends at x = 0.25 m


def scene_with_obstacle(x: float) -> sph.Scene:
    with open(ROOT / "scenes" / "dam_break_2d.toml", "rb") as f:
        table = tomllib.load(f)
    table["solid"].append(
        {"name": "obstacle", "shape": "box", "min": [x, 0.0], "max": [x + 0.05, 0.08]}
    )
    table.pop("probe")  # the surge front's reference comparison is not needed here
    return sph.Scene.from_dict(
        table,
        {"particles.spacing": 0.01},
        base_dir=ROOT / "scenes",
        end_time=0.25,
    )


def peak_force(x: float) -> float:
    sim = sph.Simulation(scene_with_obstacle(x))
    sim.run(progress=True)
    forces = sim.forces()
    on_obstacle = np.array(forces["solid"]) == "obstacle"
    return float(np.max(forces["fx_N_per_m"][on_obstacle]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("."), help="folder for sweep_obstacle.png")
    args = parser.parse_args()
    peaks = []
    for x in POSITIONS:
        peaks.append(peak_force(x))
        print(f"obstacle at x = {x:.2f} m: peak force {peaks[-1]:.1f} N per m of depth")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no figure")
        return
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot(POSITIONS, peaks, "o-")
    ax.set_xlabel("obstacle position x [m]")
    ax.set_ylabel("peak force fx [N/m]")
    ax.set_title("2D dam break: peak force on an obstacle")
    fig.tight_layout()
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "sweep_obstacle.png"
    fig.savefig(path, dpi=120)
    print(f"figure in {path}")


if __name__ == "__main__":
    main()
