"""`sph.run` and `sph.Simulation` against `sph run` of the same tree: the same files and values,
bit for bit; and a run interrupted from Python leaves the folder `sph run --resume` continues."""

import gc
import json
import re
import signal
import subprocess
import threading

import numpy as np
import pytest

import sph

END = 0.01  # four steps of the 2D dam break


def cli_run(cli, scene, out, *args):
    subprocess.run(
        [cli, "run", scene, "--end-time", str(END), "--threads", "1", "--out", out, *args],
        check=True,
        capture_output=True,
    )


def read_raw_vtu(path):
    """The point arrays of a frame written with `output.encoding = "raw"`, by name."""
    data = path.read_bytes()
    head, _, rest = data.partition(b'<AppendedData encoding="raw">')
    blob = rest[rest.index(b"_") + 1 :]
    header = {"UInt32": np.uint32, "UInt64": np.uint64}[
        re.search(rb'header_type="(\w+)"', head).group(1).decode()
    ]
    size = np.dtype(header).itemsize
    types = {"Float32": np.float32, "Float64": np.float64, "UInt32": np.uint32, "Int32": np.int32,
             "UInt8": np.uint8, "Int64": np.int64, "UInt64": np.uint64}
    arrays = {}
    for tag in re.finditer(rb"<DataArray ([^>]*)>", head):
        attrs = {k.decode(): v.decode() for k, v in re.findall(rb'(\w+)="([^"]*)"', tag.group(1))}
        if "offset" not in attrs:
            continue
        start = int(attrs["offset"])
        length = int(np.frombuffer(blob[start : start + size], dtype=header)[0])
        values = np.frombuffer(blob[start + size : start + size + length], dtype=types[attrs["type"]])
        components = int(attrs.get("NumberOfComponents", "1"))
        arrays[attrs.get("Name", "Points")] = values.reshape(-1, components) if components > 1 else values
    return arrays


def test_run_writes_the_files_sph_run_writes(tmp_path, cli, dam_break):
    cli_run(cli, dam_break, tmp_path / "cli")
    result = sph.run(dam_break, tmp_path / "py", end_time=END, threads=1, progress=False)
    assert result.status == "completed"
    for name in ["forces.csv", "probes.csv", "steps.csv", "particles.pvd"]:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    frames = sorted((tmp_path / "cli" / "frames").iterdir())
    assert frames
    for frame in frames:
        assert (tmp_path / "py" / "frames" / frame.name).read_bytes() == frame.read_bytes(), frame.name
    cli_summary = json.loads((tmp_path / "cli" / "summary.json").read_text())
    for key in ["steps", "simulated_time", "particles", "max_compression", "max_surface_deficit"]:
        assert result.summary[key] == cli_summary[key], key
    assert result.forces["solid"] == ["tank"] * result.summary["steps"]
    assert np.array_equal(result.steps["step"], np.arange(1, result.summary["steps"] + 1))


def test_simulation_equals_sph_run_bit_for_bit(tmp_path, cli, dam_break):
    cli_run(cli, dam_break, tmp_path / "cli", "--set", 'output.encoding="raw"')
    sim = sph.Simulation(sph.Scene.load(dam_break, end_time=END), threads=1)
    sim.run(progress=False)
    for name, table in [("forces", sim.forces()), ("probes", sim.probes()), ("steps", sim.steps())]:
        written = sph.read_table(tmp_path / "cli" / f"{name}.csv")
        assert list(table) == list(written), name
        for column, values in table.items():
            if isinstance(values, list):
                assert values == written[column], (name, column)
            else:
                assert np.array_equal(np.asarray(values), written[column]), (name, column)
    frames = sorted((tmp_path / "cli" / "frames").glob("*.vtu"))
    last = read_raw_vtu(frames[-1])
    fields = sim.fields()
    order = np.argsort(fields["id"])
    frame_order = np.argsort(last["id"])
    assert np.array_equal(fields["id"][order], last["id"][frame_order])
    points = last["Points"][frame_order]
    d = sim.dimension
    assert np.array_equal(fields["position"][order], points[:, :d])
    for name in ["density", "pressure"]:
        assert np.array_equal(fields[name][order], last[name][frame_order]), name


def test_fields_borrow_the_simulation_memory(dam_break):
    sim = sph.Simulation(sph.Scene.load(dam_break, end_time=END), threads=1)
    sim.step()
    first, second = sim.fields(), sim.fields()
    for name, array in first.items():
        assert array.__array_interface__["data"][0] == second[name].__array_interface__["data"][0], name
        assert array.flags.writeable is False, name
        assert array.base is not None, name
        with pytest.raises(ValueError):
            array[...] = 0
    assert first["position"].shape == (sim.particle_count, 2)
    assert first["position"].dtype == np.float32
    assert first["id"].dtype == np.uint32


def test_fields_kept_across_steps_stay_the_state_they_were_taken_at(root):
    # The open channel's inflow creates particles once its buffer has moved by a spacing (after
    # about 0.25 s of its ramp, some 400 steps): the particle count changes and the solver's
    # buffers are reallocated while the old arrays are held.
    scene = sph.Scene.load(root / "scenes" / "open_channel_2d.toml", end_time=1.0)
    sim = sph.Simulation(scene, threads=1)
    old = sim.fields()
    assert len({id(array.base) for array in old.values()}) == 1  # one guard per call
    snapshot = {name: np.array(array, copy=True) for name, array in old.items()}
    count = sim.particle_count
    middle = middle_snapshot = None
    changed = 0
    while sim.time < sim.end_time and changed < 3:
        row = sim.step()
        if row["created_particles"] or row["removed_particles"]:
            changed += 1
            if middle is None:  # a second generation, held over the next changes too
                middle = sim.fields()
                middle_snapshot = {name: np.array(array, copy=True) for name, array in middle.items()}
            else:
                sim.fields()  # a generation dropped at once
    assert changed == 3, "fewer than three steps created or removed particles"
    assert sim.particle_count != count
    for name, array in old.items():
        assert array.shape[0] == count, name
        assert array.tobytes() == snapshot[name].tobytes(), name
    for name, array in middle.items():
        assert array.tobytes() == middle_snapshot[name].tobytes(), name
    new = sim.fields()
    assert new["position"].shape == (sim.particle_count, 2)
    assert new["id"].shape == (sim.particle_count,)
    assert new["position"].__array_interface__["data"][0] != old["position"].__array_interface__["data"][0]
    # The arrays outlive the simulation.
    del sim, new
    gc.collect()
    for name, array in old.items():
        assert array.tobytes() == snapshot[name].tobytes(), name


def test_the_gil_is_released_while_stepping(dam_break):
    sim = sph.Simulation(sph.Scene.load(dam_break, end_time=END), threads=1)
    worker = threading.Thread(target=sim.run, kwargs={"progress": False})
    ticks = 0
    worker.start()
    while worker.is_alive():
        ticks += 1
        worker.join(0.001)
    assert sim.time >= END
    assert ticks > 10


def test_interrupted_run_leaves_a_folder_sph_resumes(tmp_path, cli, dam_break):
    out = tmp_path / "run"

    def stop(progress):
        if progress["steps"] == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sph.run(dam_break, out, end_time=2 * END, threads=1, progress=False, callback=stop)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"].startswith("interrupted"), summary["status"]
    assert (out / "checkpoint.bin").exists()
    assert len(sph.read_table(out / "steps.csv")["step"]) == summary["steps"]
    subprocess.run([cli, "run", "--resume", out], check=True, capture_output=True)
    resumed = json.loads((out / "summary.json").read_text())
    assert resumed["status"] == "completed"
    # The resumed run equals one that was never interrupted.
    subprocess.run(
        [cli, "run", dam_break, "--end-time", str(2 * END), "--threads", "1", "--out", tmp_path / "whole"],
        check=True,
        capture_output=True,
    )
    for name in ["forces.csv", "steps.csv", "probes.csv"]:
        assert (out / name).read_bytes() == (tmp_path / "whole" / name).read_bytes(), name


def test_sigint_interrupts_a_run_as_ctrl_c(tmp_path, dam_break):
    out = tmp_path / "run"

    def ctrl_c(progress):
        if progress["steps"] == 1:
            signal.raise_signal(signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        sph.run(dam_break, out, end_time=2 * END, threads=1, progress=False, callback=ctrl_c)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"].startswith("interrupted"), summary["status"]
    assert (out / "checkpoint.bin").exists()


def test_a_callback_error_propagates_after_a_consistent_stop(tmp_path, dam_break):
    def fail(progress):
        raise ValueError("stop here")

    with pytest.raises(ValueError, match="stop here"):
        sph.run(dam_break, tmp_path / "run", end_time=END, threads=1, progress=False, callback=fail)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["status"].startswith("interrupted")


def test_cuda_without_the_feature_is_a_solver_error(tmp_path, dam_break):
    if sph.CUDA_FEATURE:
        return
    with pytest.raises(sph.SolverError, match="cuda"):
        sph.Simulation(sph.Scene.load(dam_break), backend="cuda")
    with pytest.raises(sph.SolverError, match="cuda"):
        sph.run(dam_break, tmp_path / "run", end_time=END, backend="cuda", progress=False)
    with pytest.raises(ValueError):
        sph.Simulation(sph.Scene.load(dam_break), backend="tpu")
