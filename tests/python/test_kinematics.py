# FK / IK of the built-in PUMA 560 and of a URDF arm through the asimov module.
import numpy as np
import pytest

import asimov


def random_joints(robot, rng, margin=0.1):
    lo, hi = robot.lower, robot.upper
    span = hi - lo
    return lo + span * margin + rng.random(robot.joint_count) * span * (1 - 2 * margin)


@pytest.mark.parametrize("arm", ["puma560", "generic6"])
def test_ik_reproduces_fk(root, arm):
    robot = asimov.puma560() if arm == "puma560" else asimov.load_urdf(str(root / "robots/data/generic6.urdf"))
    rng = np.random.default_rng(7)
    solved = 0
    for _ in range(50):
        q = random_joints(robot, rng)
        flange = robot.fk(q)
        assert flange.shape == (4, 4) and np.allclose(flange[3], [0, 0, 0, 1])
        try:
            sol = robot.ik(flange, current=q + 1.0, config=robot.configuration(q))
        except asimov.KinematicsError:
            continue  # a limit in the requested configuration; counted below
        assert np.allclose(robot.fk(sol), flange, atol=1e-5)
        solved += 1
    assert solved >= 45


def test_link_frames_end_at_the_flange():
    robot = asimov.puma560()
    q = robot.ready
    frames = robot.link_frames(q)
    assert frames.shape == (robot.joint_count + 1, 4, 4)
    assert np.allclose(frames[0], np.eye(4))
    assert np.allclose(frames[-1], robot.fk(q))


def test_unreachable_and_bad_input():
    robot = asimov.puma560()
    with pytest.raises(asimov.KinematicsError) as e:
        robot.ik(asimov.trans(5000, 0, 0))
    assert e.value.message == "*Location out of reach*"
    with pytest.raises(ValueError):
        robot.fk([1, 2, 3])
    with pytest.raises(ValueError):
        robot.ik(np.eye(3))


def test_urdf_errors(tmp_path):
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'/><joint name='j' type='revolute'>\n</robot>")
    with pytest.raises(asimov.RobotError) as e:
        asimov.load_urdf(str(bad))
    assert e.value.file.endswith("bad.urdf")


def test_trans_decompose_round_trip():
    x = (100.0, -20.0, 300.0, 30.0, 60.0, -45.0)
    assert np.allclose(asimov.decompose(asimov.trans(*x)), x)
