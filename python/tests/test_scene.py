"""Scene loading, overrides, dict scenes, `check()`, and errors carrying `sph`'s messages."""

import subprocess

import pytest

import sph


def test_load_applies_overrides_as_sph_run_set(dam_break):
    scene = sph.Scene.load(dam_break, {"solver.cfl": 0.1}, end_time=0.02)
    assert scene.dimension == 2
    assert scene.end_time == 0.02
    assert scene.name == "dam_break_2d"
    assert scene.solids == ["tank"]
    assert scene.probes == ["front"]
    assert scene.overrides == ["solver.cfl=0.1", "solver.end_time=0.02"]


def test_check_prints_what_sph_check_prints(dam_break, cli):
    scene = sph.Scene.load(dam_break)
    printed = subprocess.run([cli, "check", dam_break], capture_output=True, text=True, check=True)
    assert scene.check() == printed.stdout


def test_scene_from_a_dict_equals_the_file(dam_break):
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+
    with open(dam_break, "rb") as f:
        table = tomllib.load(f)
    from_dict = sph.Scene.from_dict(table, end_time=0.01)
    from_file = sph.Scene.load(dam_break, end_time=0.01)
    assert from_dict.path is None
    assert from_dict.check().splitlines()[1:] == from_file.check().splitlines()[1:]


def test_bad_scene_raises_the_message_sph_prints(tmp_path, cli):
    bad = tmp_path / "bad.toml"
    bad.write_text('dimension = 2\nname = "bad"\n[particles]\nspacing = -1.0\n')
    with pytest.raises(sph.SceneError) as caught:
        sph.Scene.load(bad)
    message = str(caught.value)
    assert "\n" not in message
    run = subprocess.run([cli, "run", bad, "--out", tmp_path / "out"], capture_output=True, text=True)
    assert run.returncode == 1
    assert run.stderr.strip().splitlines()[-1] == f"error: {message}"
    # `sph check` names the same problems after its own context.
    check = subprocess.run([cli, "check", bad], capture_output=True, text=True)
    reason = message.removeprefix(f"loading scene {bad}: ")
    assert check.stderr.strip().splitlines()[-1] == f"error: checking scene {bad}: {reason}"


def test_bad_override_is_a_scene_error(dam_break):
    with pytest.raises(sph.SceneError, match="solver.cfl"):
        sph.Scene.load(dam_break, {"solver.cfl": -1.0})
    with pytest.raises(sph.SceneError, match="no_such_key"):
        sph.Scene.load(dam_break, {"solver.no_such_key": 1})


def test_missing_file_is_a_scene_error(tmp_path):
    with pytest.raises(sph.SceneError, match="loading scene"):
        sph.Scene.load(tmp_path / "missing.toml")
    assert issubclass(sph.SceneError, sph.SphError)
