"""Checks that `sph run` split across ranks under mpirun wrote what one rank writes.

Usage: compare_split_run.py WHOLE_DIR SPLIT_DIR RANKS

- summary.json: both completed, the same particles, fluid particles and fluid mass, the
  split one names RANKS ranks, and the step counts within 2 % (the time step follows the
  largest speed, which rounding moves);
- steps.csv, forces.csv and probes.csv: the same columns; the front (probes.csv) within 1 mm
  at every sample time the two share within 0.1 ms;
- particles.pvd: the same number of frames, each a .pvtu of RANKS pieces that VTK reads as
  one dataset holding every particle once.
"""

import csv
import json
import sys
from pathlib import Path

import vtk
from vtk.util.numpy_support import vtk_to_numpy


def rows(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def main():
    whole, split, ranks = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3])
    a = json.loads((whole / "summary.json").read_text())
    b = json.loads((split / "summary.json").read_text())
    assert a["status"] == b["status"] == "completed", (a["status"], b["status"])
    for key in ["particles", "fluid_particles"]:
        assert a[key] == b[key], (key, a[key], b[key])
    assert a["extra"]["fluid_mass"] == b["extra"]["fluid_mass"]
    assert b["extra"]["ranks"] == ranks, b["extra"].get("ranks")
    assert abs(a["steps"] - b["steps"]) <= 0.02 * a["steps"], (a["steps"], b["steps"])
    for name in ["steps.csv", "forces.csv", "probes.csv"]:
        assert rows(whole / name)[0] == rows(split / name)[0], name
    front_a = {round(float(r[0]), 4): float(r[1]) for r in rows(whole / "probes.csv")[1:]}
    shared = 0
    for r in rows(split / "probes.csv")[1:]:
        t = round(float(r[0]), 4)
        if t in front_a:
            shared += 1
            assert abs(front_a[t] - float(r[1])) < 1e-3, (t, front_a[t], r[1])
    assert shared >= 10, shared
    frames = lambda d: [x.split('"')[0] for x in (d / "particles.pvd").read_text().split('file="')[1:]]
    fa, fb = frames(whole), frames(split)
    assert len(fa) == len(fb), (len(fa), len(fb))
    for frame in fb:
        assert frame.endswith(".pvtu"), frame
        reader = vtk.vtkXMLPUnstructuredGridReader()
        reader.SetFileName(str(split / frame))
        reader.Update()
        grid = reader.GetOutput()
        assert reader.GetNumberOfPieces() == ranks, reader.GetNumberOfPieces()
        ids = vtk_to_numpy(grid.GetPointData().GetArray("id"))
        assert len(ids) == a["particles"] and len(set(ids.tolist())) == len(ids), (frame, len(ids))
    print(f"split run on {ranks} ranks: {b['steps']} steps against {a['steps']}, {shared} front samples within 1 mm, {len(fb)} frames of {ranks} pieces")


if __name__ == "__main__":
    main()
