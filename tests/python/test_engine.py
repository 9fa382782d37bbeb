# The collision engine through the asimov module: bodies from arrays, meshes and primitives,
# poses, contact queries, batches; and agreement with the C++ engine on 10,000 random poses.
import subprocess

import numpy as np
import pytest

import asimov


def cube(side):
    h = side / 2
    v = np.array([[x, y, z] for x in (-h, h) for y in (-h, h) for z in (-h, h)], dtype=float)
    # two outward triangles per face (vertex index = 4x + 2y + z)
    t = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return v, t


def shifted(x, y=0.0, z=0.0):
    p = np.eye(4)
    p[:3, 3] = (x, y, z)
    return p


def test_bodies_from_arrays_touch_and_separate():
    e = asimov.Engine()
    a = e.add_body("a", *cube(100))
    b = e.add_body("b", *cube(100))
    assert len(e) == 2 and e.body_name(b) == "b" and e.body_closed(a)
    e.set_pose(a, np.eye(4))
    e.set_pose(b, shifted(101))
    assert e.check() is None and not e.collides()
    e.set_pose(b, shifted(100))  # face to face: touching counts
    c = e.check()
    assert c["bodies"] == ("a", "b") and c["kind"] == "faces"
    e.set_pose(b, shifted(0, 0, 10))  # overlapping
    assert e.collides()
    e.set_pair_enabled(a, b, False)
    assert not e.collides()


def test_containment_and_clearance():
    e = asimov.Engine(clearance=5)
    big = e.add_box("big", (300, 300, 300))
    small = e.add_cylinder("small", 10, 20)
    e.set_pose(big, np.eye(4))
    e.set_pose(small, np.eye(4))
    assert e.check()["kind"] == "containment"
    e.set_pose(small, shifted(150 + 10 + 3))  # 3 mm from the big box: within the clearance
    c = e.check()
    assert c["kind"] == "clearance" and 0 < c["distance"] <= 5
    e.set_clearance(0)
    assert e.check() is None


def test_mesh_file(tmp_path):
    v, t = cube(50)
    stl = tmp_path / "cube.stl"
    with open(stl, "w") as f:
        f.write("solid c\n")
        for tri in t:
            f.write(" facet normal 0 0 0\n  outer loop\n")
            for i in tri:
                f.write("   vertex %g %g %g\n" % tuple(v[i]))
            f.write("  endloop\n endfacet\n")
        f.write("endsolid c\n")
    e = asimov.Engine()
    m = e.add_mesh(str(stl))
    assert e.body_name(m) == "cube" and e.body_closed(m)
    with pytest.raises(asimov.RobotError):
        e.add_mesh(str(tmp_path / "missing.stl"))


def test_bad_input_is_rejected():
    e = asimov.Engine()
    with pytest.raises(ValueError):
        e.add_body("x", np.zeros((3, 2)), [[0, 1, 2]])
    with pytest.raises(ValueError):
        e.add_body("x", np.zeros((3, 3)), [[0, 1, 7]])
    with pytest.raises(asimov.RobotError):
        e.add_body("x", [[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]], [[0, 1, 2]])
    a = e.add_box("a", (1, 1, 1))
    with pytest.raises(IndexError):
        e.set_pose(5, np.eye(4))
    with pytest.raises(ValueError):
        e.check_poses(a, np.zeros((10, 3, 3)))
    assert e.check_poses(a, np.zeros((0, 4, 4))).shape == (0,)


def test_batch_of_several_bodies():
    e = asimov.Engine()
    a = e.add_box("a", (100, 100, 100))
    b = e.add_box("b", (100, 100, 100))
    poses = np.stack([np.stack([np.eye(4), shifted(x)]) for x in (50.0, 150.0, 99.0)])
    assert list(e.check_poses([a, b], poses)) == [True, False, True]


def read_peer(path, n):
    raw = np.fromfile(path, dtype=np.uint8)
    poses = raw[: n * 128].view(np.float64).reshape(n, 4, 4)
    return poses, raw[n * 128:].astype(bool)


def peer_scene():
    e = asimov.Engine()
    part = e.add_cylinder("part", 50, 300, 24)
    box = e.add_box("box", (400, 300, 200), static=True)
    e.set_pose(box, np.eye(4))
    return e, part


def test_agrees_with_cpp_on_10000_random_poses(engine_batch, tmp_path):
    n = 10000
    out = tmp_path / "peer.bin"
    subprocess.run([engine_batch, str(n), "15", "1", str(out)], check=True, capture_output=True)
    poses, cpp = read_peer(out, n)
    assert 0.1 * n < cpp.sum() < 0.9 * n  # both answers occur
    e, part = peer_scene()
    py = e.check_poses(part, poses)
    assert np.array_equal(py, cpp)
    # and one pose at a time through set_pose / collides
    for i in range(0, n, 997):
        e.set_pose(part, poses[i])
        assert e.collides() == cpp[i]


def test_distance_with_witness_points():
    e = asimov.Engine()
    a = e.add_box("a", (100, 100, 100))
    b = e.add_box("b", (100, 100, 100))
    e.set_pose(a, np.eye(4))
    e.set_pose(b, shifted(130, 20, 0))  # faces 30 mm apart along x
    d = e.distance(a, b)
    assert d["status"] == "exact" and abs(d["distance"] - 30) < 1e-9
    assert abs(np.linalg.norm(np.subtract(d["point_b"], d["point_a"])) - 30) < 1e-9
    assert abs(d["point_a"][0] - 50) < 1e-9 and abs(d["point_b"][0] - 80) < 1e-9
    far = e.distance(a, b, upper=10)
    assert far["status"] == "beyond" and far["distance"] >= 10
    e.set_pose(b, shifted(60))
    assert e.distance(a, b)["status"] == "contact" and e.distance(a, b)["distance"] == 0
    with pytest.raises(ValueError):
        e.distance(a, a)
    with pytest.raises(IndexError):
        e.distance(a, 9)
    # random poses: the distance is positive exactly when check() finds no contact
    rng = np.random.default_rng(3)
    for _ in range(200):
        p = shifted(*rng.uniform(-150, 150, 3))
        e.set_pose(b, p)
        d = e.distance(a, b)
        assert (d["status"] == "contact") == e.collides()
