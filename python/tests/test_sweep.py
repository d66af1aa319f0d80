"""`sph.sweep` writes the table `sph sweep` writes."""

import subprocess

import numpy as np

import sph


def test_sweep_writes_the_table_sph_sweep_writes(tmp_path, cli, dam_break):
    end = 0.005
    result = sph.sweep(dam_break, {"solver.cfl": [0.1, 0.2]}, tmp_path / "py", end_time=end, threads=1,
                       progress=False)
    subprocess.run(
        [cli, "sweep", dam_break, "--set", "solver.cfl=0.1,0.2", "--end-time", str(end), "--threads", "1",
         "--out", tmp_path / "cli"],
        check=True,
        capture_output=True,
    )
    assert [v["status"] for v in result.variants] == ["completed", "completed"]
    assert result.keys == ["solver.cfl"]
    table = result.table
    written = sph.read_table(tmp_path / "cli" / "sweep.csv")
    assert list(table) == list(written)
    for column in table:
        if "wall" in column or "per_s" in column:  # timings
            continue
        values, expected = table[column], written[column]
        if isinstance(values, list):
            assert values == expected, column
        else:
            assert np.array_equal(values, expected, equal_nan=True), column
    for run in result.runs:
        cli_dir = tmp_path / "cli" / run.out.name
        assert (run.out / "forces.csv").read_bytes() == (cli_dir / "forces.csv").read_bytes()
    assert result.runs[0].summary["status"] == "completed"
