# The module as a Python user expects it (issue #33): exceptions that say where a program stopped,
# V+'s configuration words, built-in arms by name, clear refusals (trace, duplicate names, busy
# objects, bad sizes), reprs, Jacobian, every IK solution, the replay page, a failed call that
# leaves the engine as it was (issue #29).
import os
import subprocess
import sys
import threading

import numpy as np
import pytest

import asimov


def test_command_error_of_a_collision_carries_program_line_kind_report(root):
    s = asimov.Session()
    s.load(str(root / "programs/demo/crash.v2"))
    with pytest.raises(asimov.CommandError) as e:
        s.execute("EXECUTE crash")
    err = e.value
    assert err.kind == "collision"
    assert err.message == "*Collision*"
    assert err.program == "crash"
    assert err.line == 12  # the MOVE into the box
    assert err.report["status"] == "collision"
    assert err.report["collision"]["bodies"] == ["link4", "box"]
    assert "tool at x" not in err.message
    # A command that fails by itself says so.
    with pytest.raises(asimov.CommandError) as e2:
        s.execute("FROBNICATE")
    assert e2.value.kind == "command"


def test_status_after_session_run_tells_the_run(root):
    s = asimov.Session()
    assert s.status == "idle"
    s.load(str(root / "programs/demo/crash.v2"))
    report = s.run()
    assert report["status"] == "collision"
    assert s.status == "collision"
    status = s.execute("STATUS")
    assert "idle" not in status.lower()
    assert "crash" in status.lower()


def test_ik_takes_the_v_plus_words_and_refuses_others():
    puma = asimov.puma560()
    q = np.array([10.0, -80, 100, 20, 30, 40])
    flange = puma.fk(q)
    solutions = puma.ik_all(flange, current=q)
    assert len(solutions) >= 4
    for sol in solutions:
        c = puma.configuration(sol)
        # The same configuration asked in V+'s words, negative ones included, any case.
        words = {"lefty": not c["righty"], "BELOW": not c["above"], "flip": not c["noflip"]}
        got = puma.ik(flange, current=q, config=words)
        assert puma.configuration(got) == c
        assert np.allclose(puma.fk(got), flange, atol=1e-6)
        # Only some words: the others are those of `current`.
        partial = puma.ik(flange, current=sol, config={"righty": c["righty"]})
        assert puma.configuration(partial) == c
    with pytest.raises(ValueError, match="unknown word 'elbow_up'"):
        puma.ik(flange, config={"elbow_up": True})
    with pytest.raises(TypeError, match="True or False"):
        puma.ik(flange, config={"lefty": 1})
    with pytest.raises(ValueError, match="contradict"):
        puma.ik(flange, config={"lefty": True, "righty": True})
    with pytest.raises(TypeError):
        puma.ik(flange, config=["lefty"])


def test_builtin_robot_by_name():
    viper = asimov.robot("viper_s650")
    assert viper.name == "viper_s650" and viper.joint_count == 6
    assert asimov.robot("cobra_s600").joint_count == 4
    assert np.allclose(asimov.robot("puma560").fk(np.zeros(6)), asimov.puma560().fk(np.zeros(6)))
    with pytest.raises(asimov.RobotError, match="viper_s650"):
        asimov.robot("ur5")


def test_trace_without_trace_true_says_to_ask_for_it(root):
    s = asimov.Session()
    with pytest.raises(asimov.ProgramError, match="trace=True"):
        s.trace()
    t = asimov.Session(trace=True)
    t.load(str(root / "programs/demo/crash.v2"))
    t.run()
    assert t.trace()["joints"].shape[0] > 0


def test_engine_refuses_duplicate_names_and_keeps_state_after_a_failed_add():
    e = asimov.Engine()
    a = e.add_box("first", (10, 10, 10))
    with pytest.raises(ValueError, match="already"):
        e.add_box("first", (5, 5, 5))
    with pytest.raises(ValueError, match="finite"):
        e.add_box("broken", (float("nan"), 1, 1))
    with pytest.raises(ValueError, match="finite"):
        e.add_cylinder("c", -1, 10)
    b = e.add_box("second", (10, 10, 10))
    assert len(e) == 2 and b == a + 1
    hit = e.check()
    assert hit is not None and set(hit["bodies"]) == {"first", "second"}
    # Tessellation limits as the cell files: 4096 segments at most (10**9 reached 5.4 GB).
    with pytest.raises(ValueError, match="4096"):
        e.add_cylinder("huge", 10, 10, segments=10**9)
    e.add_cylinder("max", 10, 10, segments=4096)
    assert len(e) == 3


def test_concurrent_use_is_refused_not_a_crash():
    e = asimov.Engine()
    ids = [e.add_cylinder(f"c{k}", 20, 100, segments=512) for k in range(2)]
    poses = np.tile(np.eye(4), (20000, 1, 1))
    poses[:, 0, 3] = np.linspace(0, 200, poses.shape[0])
    errors = []

    def work():
        for _ in range(5):
            try:
                e.check_poses(ids[0], poses)
            except asimov.BusyError as x:
                errors.append(x)

    for _ in range(20):
        threads = [threading.Thread(target=work) for _ in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        if errors:
            break
    assert errors, "four threads on one Engine: at least one was refused"
    assert "another thread" in errors[0].detail
    assert e.check_poses(ids[0], poses[:10]).shape == (10,)  # usable again afterwards

    # A run takes a few ms: the threads start together (a barrier) and the race is tried again
    # until one is refused (under a loaded machine one attempt may not overlap).
    s = asimov.Session()
    s.load_source(".PROGRAM spin()\n FOR i = 1 TO 2000000\n  x = i\n END\n.END\n", "spin.v2")
    busy = []

    def run(barrier):
        barrier.wait()
        try:
            s.run("spin")
        except asimov.BusyError as x:
            busy.append(x)

    for _ in range(50):
        barrier = threading.Barrier(3)
        runners = [threading.Thread(target=run, args=(barrier,)) for _ in range(3)]
        for t in runners:
            t.start()
        for t in runners:
            t.join()
        if busy:
            break
    assert busy, "three threads on one Session: none was refused in 50 tries"


def test_reprs_say_what_it_is():
    assert repr(asimov.puma560()) == "<asimov.Robot 'puma560': 6 joints (RRRRRR), 7 bodies>"
    assert "robot 'puma560'" in repr(asimov.default_cell())
    s = asimov.Session()
    assert repr(s).startswith("<asimov.Session robot 'puma560', no file, idle")
    e = asimov.Engine()
    e.add_box("a", (1, 1, 1))
    assert repr(e) == "<asimov.Engine 1 body: a>"


def test_jacobian_matches_finite_differences():
    for robot, q in ((asimov.puma560(), [10.0, -80, 100, 20, 30, 40]), (asimov.robot("cobra_s600"), [20.0, 30, 50, 10])):
        q = np.array(q)
        j = robot.jacobian(q)
        assert j.shape == (6, robot.joint_count)
        h = 1e-6
        for k in range(robot.joint_count):
            dq = np.zeros_like(q)
            dq[k] = h
            a, b = robot.fk(q + dq), robot.fk(q - dq)
            v = (a[:3, 3] - b[:3, 3]) / (2 * h)
            dr = (a[:3, :3] - b[:3, :3]) / (2 * h) @ robot.fk(q)[:3, :3].T
            w = np.array([dr[2, 1], dr[0, 2], dr[1, 0]])
            assert np.allclose(j[:3, k], v, atol=1e-5)
            assert np.allclose(j[3:, k], w, atol=1e-8)


def test_ik_all_gives_every_configuration():
    puma = asimov.puma560()
    q = np.array([10.0, -80, 100, 20, 30, 40])
    sols = puma.ik_all(puma.fk(q), current=q)
    # One per configuration that ik() reaches within the limits, each FK-exact, the original among them.
    reached = 0
    for k in range(8):
        words = {"righty": k & 4 == 0, "above": k & 2 == 0, "noflip": k & 1 == 0}
        try:
            puma.ik(puma.fk(q), current=q, config=words, single=False)
            reached += 1
        except asimov.KinematicsError:
            pass
    assert len(sols) == reached >= 4
    configs = {tuple(puma.configuration(s).values()) for s in sols}
    assert len(configs) == len(sols)
    assert any(np.allclose(s, q, atol=1e-6) for s in sols)
    for s in sols:
        assert np.allclose(puma.fk(s), puma.fk(q), atol=1e-6)
    assert puma.ik_all(asimov.trans(5000, 0, 0)) == []


def test_write_replay(root, tmp_path):
    s = asimov.Session(replay=True)
    with pytest.raises(asimov.ProgramError, match="nothing has run"):
        s.write_replay(tmp_path / "early.html")
    s.load(str(root / "programs/demo/crash.v2"))
    s.run()
    out = tmp_path / "crash.html"
    try:
        s.write_replay(out)
    except asimov.ProgramError as e:  # the viewer's three.js is not installed in this build
        assert e.message == "*Cannot write file*" and "three" in e.detail
        pytest.skip(e.detail)
    page = out.read_text()
    assert "<html" in page.lower() and "link4" in page
    with pytest.raises(asimov.ProgramError, match="replay=True"):
        asimov.Session().write_replay(tmp_path / "no.html")


def test_missing_numpy_is_said_at_import(tmp_path):
    (tmp_path / "numpy").mkdir()
    (tmp_path / "numpy" / "__init__.py").write_text("raise ImportError('no numpy here')\n")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(tmp_path)] + [p for p in sys.path if p])
    r = subprocess.run([sys.executable, "-c", "import asimov"], env=env, capture_output=True, text=True)
    assert r.returncode != 0
    assert "asimov needs NumPy" in r.stderr


def test_stubs_pass_mypy_strict(tmp_path):
    mypy = pytest.importorskip("mypy.api")
    script = tmp_path / "use_asimov.py"
    script.write_text(
        "import numpy as np\n"
        "import asimov\n\n"
        "def main() -> float:\n"
        "    robot: asimov.Robot = asimov.robot('viper_s650')\n"
        "    q = robot.ik(robot.fk(robot.ready), config={'lefty': False})\n"
        "    j = robot.jacobian(q)\n"
        "    e = asimov.Engine()\n"
        "    a = e.add_box('a', (1.0, 2.0, 3.0))\n"
        "    hit = e.check()\n"
        "    s = asimov.Session(trace=True)\n"
        "    report = asimov.run('x.v2', cell=None, trace=True)\n"
        "    try:\n"
        "        s.execute('STATUS')\n"
        "    except asimov.CommandError as err:\n"
        "        print(err.kind, err.line, err.program)\n"
        "    every = robot.ik_all(robot.fk(robot.ready))\n"
        "    words: dict[str, bool] = robot.configuration(q)\n"
        "    s.write_replay('run.html')\n"
        "    t = s.trace()['joints']\n"
        "    state: str = s.status\n"
        "    try:\n"
        "        robot.ik(robot.fk(robot.ready), config={'below': True, 'flip': False})\n"
        "    except asimov.KinematicsError as err:\n"
        "        print(err.joint, err.value)\n"
        "    try:\n"
        "        s.execute('EXECUTE prog')\n"
        "    except asimov.CommandError as err:\n"
        "        print(err.report.get('collision'), err.output, err.message)\n"
        "    schema: int = asimov.SCHEMA_VERSION\n"
        "    return (float(j[0, 0]) + a + (0.0 if hit is None else 1.0) + len(report) + float(np.sum(q)) + len(every)\n"
        "            + len(words) + float(t.size) + len(state) + schema)\n")
    # A script that misuses the API is caught.
    bad = tmp_path / "bad.py"
    bad.write_text("import asimov\nx: int = asimov.robot(5)\n")
    # So is a wrong type for a new call (ik_all returns a list of arrays, STATUS a string).
    bad2 = tmp_path / "bad2.py"
    bad2.write_text("import asimov\nn: int = asimov.robot('viper_s650').ik_all([])\ns: int = asimov.Session().status\n")
    pkg = os.path.dirname(os.path.dirname(asimov.__file__))
    env_path = os.environ.get("MYPYPATH")
    os.environ["MYPYPATH"] = pkg
    try:
        out, err, rc = mypy.run(["--strict", "--no-incremental", "--cache-dir", os.devnull, str(script)])
        assert rc == 0, out + err
        out, err, rc = mypy.run(["--strict", "--no-incremental", "--cache-dir", os.devnull, str(bad)])
        assert rc != 0 and "robot" in out
        out, err, rc = mypy.run(["--strict", "--no-incremental", "--cache-dir", os.devnull, str(bad2)])
        assert rc != 0 and "bad2.py:2" in out and "bad2.py:3" in out, out
    finally:
        if env_path is None:
            del os.environ["MYPYPATH"]
        else:
            os.environ["MYPYPATH"] = env_path


def test_stubs_match_the_module_stubtest():
    """mypy's stubtest compares the .pyi stubs with the built module: every name the module has is in
    the stubs and the other way round, with the same kinds of values. The allowlist holds what
    pybind11 cannot show: its metaclass, the constructor of classes made only by the module, and the
    stubs' own type aliases."""
    pytest.importorskip("mypy.stubtest")
    allow = os.path.join(os.path.dirname(__file__), "stubtest_allowlist.txt")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.dirname(os.path.dirname(asimov.__file__))
    r = subprocess.run([sys.executable, "-m", "mypy.stubtest", "asimov", "--allowlist", allow],
                       env=env, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
