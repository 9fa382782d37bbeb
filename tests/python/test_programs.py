# Programs, reports, traces, cells and errors through the asimov module.
import json
import threading
import time

import numpy as np
import pytest

import asimov


def test_version_and_schema():
    assert asimov.__version__.count(".") == 2
    assert asimov.SCHEMA_VERSION >= 1


def test_crash_reports_the_contact(root):
    r = asimov.run(str(root / "programs/demo/crash.v2"))
    assert r["collision"]["bodies"] == ["link4", "box"]
    assert r["status"] == "collision"
    assert r["line"] == 12 and r["program"] == "crash"
    assert 3.3 <= r["collision"]["time_s"] <= 3.5
    assert r["schema_version"] == asimov.SCHEMA_VERSION


def test_report_is_the_cli_report(root, tmp_path, cli):
    # Same document as `asimov run --report` apart from wall-clock timings.
    import subprocess
    exe = cli
    path = tmp_path / "r.json"
    subprocess.run([exe, "run", str(root / "programs/demo/crash.v2"), "--report", str(path)],
                   capture_output=True, check=False)
    cli = json.loads(path.read_text())
    py = asimov.run(str(root / "programs/demo/crash.v2"))
    for doc in (cli, py):
        doc.pop("timing")
        doc.pop("file")
    assert cli == py


def test_type_output_and_trace(root):
    import io
    out = io.StringIO()
    r = asimov.run(str(root / "programs/demo/pick_place.v2"), trace=True, stdout=out)
    assert r["status"] == "completed"
    t = r["trace"]
    n = r["poses_checked"]
    assert t["time_s"].shape == (n,) and t["joints"].shape == (n, 6)
    assert t["tool"].shape == (n, 4, 4) and t["xyzoat"].shape == (n, 6)
    assert np.all(np.diff(t["time_s"]) >= 0)
    # tool = BASE . FK(joints) . TOOL at every sample (default cell)
    cell = asimov.default_cell()
    for i in (0, n // 2, n - 1):
        expect = cell.base @ cell.robot.fk(t["joints"][i]) @ cell.tool
        assert np.allclose(t["tool"][i], expect, atol=1e-6)
        assert np.allclose(asimov.trans(*t["xyzoat"][i]), t["tool"][i], atol=1e-6)


def test_cell_from_dict_matches_the_file(root):
    cells = root / "programs/cells"
    d = {
        "robot": "../../robots/data/generic6.urdf",
        "tool": [0, 0, 150, 0, 0, 0],
        "tool_shape": {"box": [40, 60, 120], "at": [0, 0, 70, 0, 0, 0]},
        "objects": [
            {"name": "table", "box": [600, 1000, 40], "at": [750, 0, 380, 0, 0, 0]},
            {"name": "crate", "box": [150, 150, 200], "at": [700, 350, 500, 0, 0, 0]},
        ],
        "collision": {"halvings": 9, "step_mm": 1.0, "clearance_mm": 0},
    }
    from_dict = asimov.load_cell(d, base_dir=str(cells))
    from_file = asimov.load_cell(str(cells / "generic6_cell.yaml"))
    assert from_dict.objects == from_file.objects == ["table", "crate"]
    assert from_dict.robot.joint_count == 6
    a = asimov.run(str(cells / "generic6_demo.v2"), cell=from_dict)
    b = asimov.run(str(cells / "generic6_demo.v2"), cell=from_file)
    for key in ("status", "line", "sim_time_s", "poses_checked", "collision"):
        assert a.get(key) == b.get(key)


def test_cell_errors_carry_file_line_column(root, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("robot: puma560\nobjects:\n  - {name: t, box: [1, 2]}\n")
    with pytest.raises(asimov.CellError) as e:
        asimov.load_cell(str(bad))
    assert e.value.file.endswith("bad.yaml") and e.value.line == 3 and e.value.column > 0
    with pytest.raises(asimov.CellError) as e:
        asimov.load_cell({"robot": "no-such-arm"})
    assert e.value.file == "<dict>" and e.value.line >= 1
    with pytest.raises(asimov.CellError) as e:
        asimov.load_cell(str(tmp_path / "missing.yaml"))
    assert e.value.message == "*File not found*"
    assert isinstance(e.value, asimov.Error)


def test_load_error_carries_val_message_and_position():
    s = asimov.Session()
    with pytest.raises(asimov.LoadError) as e:
        s.load_source(".PROGRAM main()\n    MOVE (\n.END\n", "bad.v2")
    err = e.value
    assert err.message.startswith("*") and err.file == "bad.v2" and err.line == 2 and err.column > 0
    assert err.diagnostics and err.diagnostics[0]["line"] == 2
    assert "bad.v2" in str(err)
    with pytest.raises(asimov.LoadError) as e:
        s.load("no/such/file.v2")
    assert e.value.message == "*File not found*"


def test_runtime_error_is_an_exception_with_the_report():
    s = asimov.Session()
    s.load_source(".PROGRAM main()\n    x = 1\n    y = x / 0\n.END\n", "div.v2")
    with pytest.raises(asimov.ProgramError) as e:
        s.run()
    assert e.value.line == 3 and e.value.program == "main"
    assert e.value.report["status"] == "error" and e.value.report["error"]["line"] == 3
    with pytest.raises(asimov.ProgramError):
        s.run("nope")


def test_monitor_session():
    s = asimov.Session()
    s.execute("DO MOVE #PPOINT(10, -80, 100, 0, 30, 0)")
    assert np.allclose(s.joints, [10, -80, 100, 0, 30, 0], atol=1e-9)
    s.execute("HERE p")
    where = s.execute("WHERE")
    assert "X" in where and "J1" in where
    assert "p" in s.execute("LISTL")
    assert np.allclose(s.here, s.cell.base @ s.robot.fk(s.joints) @ s.cell.tool)
    s.execute("DO TYPE 6 * 7")
    assert "42" in s.output()
    with pytest.raises(asimov.CommandError) as e:
        s.execute("FROBNICATE")
    assert e.value.output
    assert s.execute("FROBNICATE", check=False)
    assert s.time_s > 0


def test_gil_released_during_runs(root):
    s = asimov.Session()
    s.load(str(root / "programs/demo/pick_place.v2"))
    ticks = 0
    done = threading.Event()

    def work():
        s.run()
        done.set()

    th = threading.Thread(target=work)
    t0 = time.perf_counter()
    th.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    th.join()
    elapsed = time.perf_counter() - t0
    # With the GIL held for the whole run the loop could not tick while it goes on.
    assert elapsed < 0.05 or ticks >= 5
