# Every JSON document asimov writes validates against its schema in docs/schema/ (report,
# trace, replay data; the Python report dict too), and carries schema_version.
import json
import re
import subprocess

import pytest

import asimov

jsonschema = pytest.importorskip("jsonschema")


def schema(root, name):
    return json.loads((root / "docs/schema" / f"{name}.schema.json").read_text())


def validate(root, name, doc):
    s = schema(root, name)
    jsonschema.Draft7Validator.check_schema(s)
    jsonschema.validate(doc, s)
    assert doc["schema_version"] == asimov.SCHEMA_VERSION


def run(cli, args, cwd=None):
    return subprocess.run([cli, "run", *args], capture_output=True, text=True, cwd=cwd)


CASES = [  # (program, extra args, expected exit code)
    ("programs/demo/crash.v2", [], 3),
    ("programs/demo/pick_place.v2", [], 0),
    ("programs/cells/generic6_demo.v2", ["--cell", "programs/cells/generic6_cell.yaml"], None),
    ("programs/cells/belt_pick.v2", ["--cell", "programs/cells/belt_cell.yaml"], 0),  # parts, devices, signals
    ("programs/cells/carried_crash.v2", ["--cell", "programs/cells/carried_crash_cell.yaml"], 3),
    ("programs/cells/reacti_sensor.v2", ["--cell", "programs/cells/reacti_sensor_cell.yaml"], 0),  # reaction_stops
]


@pytest.mark.parametrize("program,extra,rc", CASES)
def test_report_trace_and_replay_validate(root, cli, tmp_path, program, extra, rc):
    report, trace, page = tmp_path / "r.json", tmp_path / "t.json", tmp_path / "p.html"
    args = [program, *extra, "--report", str(report), "--trace", str(trace)]
    if (root / "app/replay/node_modules/three").is_dir():
        args += ["--replay", str(page)]
    p = run(cli, args, cwd=root)
    if rc is not None:
        assert p.returncode == rc, p.stderr
    validate(root, "report", json.loads(report.read_text()))
    validate(root, "trace", json.loads(trace.read_text()))
    if page.exists():
        m = re.search(r'<script type="application/json" id="asimov-replay-data">(.*?)</script>', page.read_text(), re.S)
        assert m
        validate(root, "replay", json.loads(m.group(1).replace("<\\/", "</")))


def test_error_reports_validate(root, cli, tmp_path):
    bad = tmp_path / "bad.v2"
    bad.write_text(".PROGRAM main()\n    MOVE (\n.END\n")
    div = tmp_path / "div.v2"
    div.write_text(".PROGRAM main()\n    x = 0\n    TYPE 1 / x\n.END\n")
    for path, rc in ((bad, 2), (div, 2)):
        report = tmp_path / (path.stem + ".json")
        p = run(cli, [str(path), "--report", str(report)])
        assert p.returncode == rc, p.stderr
        doc = json.loads(report.read_text())
        assert doc["status"] == "error"
        validate(root, "report", doc)


def test_dash_is_stdout(root, cli):
    p = run(cli, ["programs/demo/crash.v2", "--report", "-"], cwd=root)
    assert p.returncode == 3
    # TYPE output first, then the report
    start = p.stdout.index("{")
    assert p.stdout[:start].startswith("tool at x")
    doc = json.loads(p.stdout[start:])
    validate(root, "report", doc)
    assert not (root / "-").exists()
    p = run(cli, ["programs/demo/pick_place.v2", "--trace", "-"], cwd=root)
    validate(root, "trace", json.loads(p.stdout[p.stdout.index("{"):]))
    p = run(cli, ["programs/demo/crash.v2", "--report", "-", "--trace", "-"], cwd=root)
    assert p.returncode == 1 and "stdout" in p.stderr


def test_python_reports_validate(root):
    validate(root, "report", asimov.run(str(root / "programs/demo/crash.v2")))
    s = asimov.Session()
    s.load_source(".PROGRAM main()\n    x = 0\n    TYPE 1 / x\n.END\n", "div.v2")
    with pytest.raises(asimov.ProgramError) as e:
        s.run()
    validate(root, "report", e.value.report)


def test_version(cli):
    p = subprocess.run([cli, "--version"], capture_output=True, text=True)
    assert p.returncode == 0 and p.stdout.strip() == "asimov " + asimov.__version__
