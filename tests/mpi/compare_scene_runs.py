"""Checks that a short run of a scene under mpirun ends as the run on one rank does.

Usage: compare_scene_runs.py WHOLE_DIR SPLIT_DIR RANKS NAME

- summary.json: both completed, the split one on RANKS ranks, the same steps, particles and
  fluid particles, fluid mass within 1e-9 of itself (summed over ranks in another order), and
  the same particles created and removed;
- steps.csv: the same rows' count, and the largest compression of each step within 1e-4
  (the `corrected` solver's tolerance δ; `wcsph` agrees to rounding), also where particles
  start on top of each other (`smoothing::pair_offset` parts such a pair along a direction
  taken from the two particles' ids, the same on any number of ranks);
- the last frame: a .pvtu of RANKS pieces that VTK reads as one dataset holding as many
  particles as the one-rank frame, each once.
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


def last_frame_ids(run):
    frames = [x.split('"')[0] for x in (run / "particles.pvd").read_text().split('file="')[1:]]
    frame = frames[-1]
    parallel = frame.endswith(".pvtu")
    reader = vtk.vtkXMLPUnstructuredGridReader() if parallel else vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(run / frame))
    reader.Update()
    pieces = reader.GetNumberOfPieces() if parallel else 1
    ids = vtk_to_numpy(reader.GetOutput().GetPointData().GetArray("id")).tolist()
    return frame, pieces, ids


def main():
    whole, split, ranks, name = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    a = json.loads((whole / "summary.json").read_text())
    b = json.loads((split / "summary.json").read_text())
    assert a["status"] == b["status"] == "completed", (name, a["status"], b["status"])
    assert b["extra"]["ranks"] == ranks, (name, b["extra"].get("ranks"))
    for key in ["steps", "particles", "fluid_particles"]:
        assert a[key] == b[key], (name, key, a[key], b[key])
    for key in ["created_particles", "outflow_particles", "removed_particles"]:
        assert a["extra"].get(key) == b["extra"].get(key), (name, key)
    ma, mb = a["extra"]["fluid_mass"], b["extra"]["fluid_mass"]
    assert abs(ma - mb) <= 1e-9 * abs(ma), (name, ma, mb)
    sa, sb = rows(whole / "steps.csv"), rows(split / "steps.csv")
    assert sa[0] == sb[0] and len(sa) == len(sb), (name, len(sa), len(sb))
    k = sa[0].index("max_compression")
    compared = list(zip(sa[1:], sb[1:]))
    worst = max(abs(float(x[k]) - float(y[k])) for x, y in compared)
    assert worst <= 1e-4, (name, "max_compression", worst)
    frame_a, _, ids_a = last_frame_ids(whole)
    frame_b, pieces, ids_b = last_frame_ids(split)
    assert frame_b.endswith(".pvtu") and pieces == ranks, (name, frame_b, pieces)
    assert len(ids_b) == len(ids_a) and len(set(ids_b)) == len(ids_b), (name, len(ids_a), len(ids_b))
    print(f"{name} on {ranks} ranks: {b['steps']} steps, {len(ids_b)} particles in {pieces} pieces, compression within {worst:.1e}")


if __name__ == "__main__":
    main()
