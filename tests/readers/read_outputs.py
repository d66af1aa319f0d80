#!/usr/bin/env python3
"""Reads the frames and surfaces of `sph run` with independent readers: VTK's own XML readers
(the ones ParaView uses) and meshio, and checks what tests/output/readers.rs checks through vtkio.

    read_outputs.py --sph target/release/sph   # runs 2D and 3D dam breaks in every encoding
    read_outputs.py RUN_DIR [RUN_DIR ...]      # checks finished runs

For every run: each frame's `TimeValue` equals its time in particles.pvd (and each surface's
its time in surface.pvd); `id` is UInt32, unique, and a permutation of 0..N unless the frames are
fluid-only; between two frames each id moves by at most 2 dt max(|u|max, |g| dt) (|g| = 9.81
m/s^2), while the storage order changes; VTK and meshio read the same values, bit for bit; 2D
surfaces are line cells of 2 points, 3D surfaces triangles. With --sph, the zlib, base64 and raw
runs of one scene hold bitwise the same arrays (CPU runs are reproducible), and the fluid-only
frames hold the fluid particles of the full frames under the same ids.

Needs: pip install meshio vtk. Exits non-zero on any failure; the last line reads
"N passed, N failed".
"""

import argparse
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLUnstructuredGridReader

GRAVITY = 9.81
ENCODINGS = ["zlib", "base64", "raw"]


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def pvd_entries(path):
    root = ET.parse(path).getroot()
    check(root.get("type") == "Collection", f"{path}: not a Collection")
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def vtk_read(path):
    """Points, point arrays (name -> numpy) and TimeValue of a .vtu/.vtp by VTK's reader."""
    reader = vtkXMLPolyDataReader() if path.suffix == ".vtp" else vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    check(reader.GetErrorCode() == 0, f"{path}: VTK reader error {reader.GetErrorCode()}")
    data = reader.GetOutput()
    check(data.GetNumberOfPoints() > 0, f"{path}: VTK read no points")
    points = vtk_to_numpy(data.GetPoints().GetData())
    pd = data.GetPointData()
    arrays = {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}
    time_array = data.GetFieldData().GetArray("TimeValue")
    check(time_array is not None, f"{path}: no TimeValue field")
    return data, points, arrays, float(time_array.GetValue(0))


def check_frame_readers_agree(path):
    """VTK and meshio read the same points and arrays; returns VTK's reading."""
    data, points, arrays, time = vtk_read(path)
    check(arrays["id"].dtype == np.uint32, f"{path}: id is {arrays['id'].dtype}, not UInt32")
    check(arrays["kind"].dtype == np.uint32, f"{path}: kind is not UInt32")
    mesh = meshio.read(path)
    check(np.array_equal(mesh.points, points), f"{path}: meshio and VTK points differ")
    for name, values in arrays.items():
        other = mesh.point_data[name]
        check(other.dtype == values.dtype, f"{path}: {name} is {other.dtype} in meshio")
        check(
            np.array_equal(other.reshape(values.shape).view(np.uint8), values.view(np.uint8)),
            f"{path}: {name} differs between meshio and VTK",
        )
    check(float(mesh.field_data["TimeValue"][0]) == time, f"{path}: meshio TimeValue")
    check(data.GetNumberOfCells() == len(points), f"{path}: one vertex cell per particle")
    return points, arrays, time


def check_run(run, fluid_only=False):
    """Checks one run directory; returns the frames and surfaces it read, for comparisons."""
    frames, previous, reordered = [], None, False
    entries = pvd_entries(run / "particles.pvd")
    check(len(entries) >= 2, f"{run}: fewer than two frames")
    for t, file in entries:
        path = run / file
        points, arrays, time = check_frame_readers_agree(path)
        check(time == t, f"{path}: TimeValue {time} but {t} in particles.pvd")
        ids = arrays["id"]
        check(len(np.unique(ids)) == len(ids), f"{path}: ids repeat")
        if fluid_only:
            check(np.all(arrays["kind"] == 0), f"{path}: a solid particle in a fluid-only frame")
        else:
            check(np.array_equal(np.sort(ids), np.arange(len(ids))), f"{path}: id is not 0..N")
        order = np.argsort(ids)
        speed = float(np.max(np.linalg.norm(arrays["velocity"], axis=1)))
        if previous is not None:
            t0, ids0, points0, speed0 = previous
            check(np.array_equal(np.sort(ids0), np.sort(ids)), f"{path}: the ids change")
            moved = np.linalg.norm(
                points[order].astype(np.float64) - points0[np.argsort(ids0)].astype(np.float64), axis=1
            )
            dt = t - t0
            bound = 2.0 * dt * max(speed, speed0, GRAVITY * dt) + 1e-6
            check(moved.max() <= bound, f"{path}: particle moved {moved.max()} m, bound {bound} m")
            check(moved.max() > 0.0, f"{path}: nothing moves")
            reordered |= not np.array_equal(ids0, ids)
        previous = (t, ids, points, speed)
        frames.append((points, arrays))
    check(reordered, f"{run}: the storage order never changes, so ids are not exercised")

    surfaces = []
    if (run / "surface.pvd").exists():
        surface_entries = pvd_entries(run / "surface.pvd")
        check([t for t, _ in surface_entries] == [t for t, _ in entries], f"{run}: surface times")
        for t, file in surface_entries:
            path = run / file
            data, points, arrays, time = vtk_read(path)
            check(time == t, f"{path}: TimeValue {time} but {t} in surface.pvd")
            planar = bool(np.all(points[:, 2] == 0.0))
            cells = data.GetLines() if planar else data.GetPolys()
            size = 2 if planar else 3
            check(cells.GetNumberOfCells() > 0, f"{path}: no cells")
            offsets = vtk_to_numpy(cells.GetOffsetsArray())
            check(np.all(np.diff(offsets) == size), f"{path}: cells are not of {size} points")
            check(arrays["Normals"].shape == points.shape, f"{path}: Normals")
            connectivity = vtk_to_numpy(cells.GetConnectivityArray())
            surfaces.append((points, connectivity, arrays["Normals"]))
    return frames, surfaces


def same(a, b):
    return a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a.view(np.uint8), b.view(np.uint8))


def dam_break(dimension, output):
    """The scene of tests/output/readers.rs: a small dam break in a tank; `output` goes in [output]."""
    if dimension == 2:
        domain, fluid, tank = "[-0.1, -0.1]", "[0.2, 0.3]", "[0.6, 0.4]"
        lo, hi_domain, spacing, end, g = "[0.0, 0.0]", "[0.7, 0.5]", 0.02, 0.08, "[0.0, -9.81]"
    else:
        domain, fluid, tank = "[-0.2, -0.2, -0.2]", "[0.16, 0.24, 0.2]", "[0.4, 0.3, 0.2]"
        lo, hi_domain, spacing, end, g = "[0.0, 0.0, 0.0]", "[0.6, 0.5, 0.4]", 0.04, 0.06, "[0.0, -9.81, 0.0]"
    return f"""name = "dam"
dimension = {dimension}
effects = ["gravity"]

[domain]
min = {domain}
max = {hi_domain}

[particles]
spacing = {spacing}
smoothing_ratio = 2.0

[fluid]
rho0 = 1000.0
sound_speed = 20.0
gravity = {g}

[[fluid_box]]
min = {lo}
max = {fluid}

[[solid]]
name = "tank"
shape = "container"
min = {lo}
max = {tank}

[solver]
kind = "wcsph"
end_time = {end}

[output]
interval = {end / 4}
{output}
"""


def run_sph(sph, scene_text, folder):
    folder.mkdir(parents=True)
    scene = folder / "scene.toml"
    scene.write_text(scene_text)
    out = folder / "run"
    done = subprocess.run([sph, "run", str(scene), "--threads", "1", "--out", str(out)], capture_output=True, text=True)
    check(done.returncode == 0, f"sph run failed: {done.stderr.strip()}")
    return out


def checks_with_sph(sph, scratch):
    """(name, function) pairs: every check of the runs this script makes."""
    cases = []
    for dimension in (2, 3):
        def encodings(dimension=dimension):
            read = {}
            for encoding in ENCODINGS:
                scene = dam_break(dimension, f'surface = true\nencoding = "{encoding}"')
                read[encoding] = check_run(run_sph(sph, scene, scratch / f"{dimension}d_{encoding}"))
            frames, surfaces = read["zlib"]
            for encoding in ENCODINGS[1:]:
                other_frames, other_surfaces = read[encoding]
                for (p, a), (q, b) in zip(frames, other_frames):
                    check(same(p, q), f"{dimension}D: points differ between zlib and {encoding}")
                    for name in a:
                        check(same(a[name], b[name]), f"{dimension}D: {name} differs between zlib and {encoding}")
                check(len(surfaces) == len(other_surfaces) > 0, f"{dimension}D: surface count")
                for s, o in zip(surfaces, other_surfaces):
                    check(all(same(x, y) for x, y in zip(s, o)), f"{dimension}D: surfaces differ ({encoding})")
            return read["zlib"][0]

        def fluid_only(dimension=dimension):
            full_frames, _ = check_run(run_sph(sph, dam_break(dimension, ""), scratch / f"{dimension}d_full"))
            only_frames, _ = check_run(
                run_sph(sph, dam_break(dimension, "fluid_only = true"), scratch / f"{dimension}d_fluid"),
                fluid_only=True,
            )
            for (p, a), (q, b) in zip(full_frames, only_frames):
                fluid = a["kind"] == 0
                check(fluid.sum() == len(b["id"]) < len(a["id"]), f"{dimension}D: fluid-only count")
                want = dict(zip(a["id"][fluid].tolist(), map(tuple, p[fluid])))
                got = dict(zip(b["id"].tolist(), map(tuple, q)))
                check(want == got, f"{dimension}D: fluid-only frames differ from the fluid of full frames")

        cases.append((f"{dimension}D frames and surfaces in zlib, base64 and raw", encodings))
        cases.append((f"{dimension}D fluid-only frames", fluid_only))
    return cases


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="*", type=Path, help="finished run directories to check")
    parser.add_argument("--sph", help="the sph binary: run the 2D and 3D dam breaks and check them")
    args = parser.parse_args()
    if not args.runs and not args.sph:
        parser.error("give run directories or --sph")
    cases = [(f"run {run}", lambda run=run: check_run(run)) for run in args.runs]
    with tempfile.TemporaryDirectory(prefix="sph_read_outputs_") as tmp:
        if args.sph:
            cases += checks_with_sph(args.sph, Path(tmp))
        passed = failed = 0
        for name, case in cases:
            try:
                case()
                passed += 1
                print(f"ok      {name}")
            except Failure as e:
                failed += 1
                print(f"FAILED  {name}: {e}")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
