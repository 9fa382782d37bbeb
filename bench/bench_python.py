#!/usr/bin/env python3
"""The Python engine batch against the same loop in C++ (bench/README.md).

10,000 seeded random poses of a cylinder about a static box (tests/python/engine_batch.cpp
makes them and times its own set_pose + check loop); the same poses as one (N, 4, 4) NumPy
array through asimov.Engine.check_poses. Both warm up first (the lazy voxel grids); medians of
ROUNDS rounds, each round running the C++ peer and the Python batch one after the other so both
see the same machine load. Writes results/python_engine.json.

usage: PYTHONPATH=build/python python3 bench/bench_python.py [BUILD_DIR] [ROUNDS]
"""
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import asimov

N = 10000
REPEATS = 5  # passes per measurement (the peer reports its median over these)


def main():
    build = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "build")
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    peer = build / "tests" / "asimov_engine_batch"
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "peer.bin"
        cpp_s, py_s = [], []
        for _ in range(rounds):
            p = subprocess.run([str(peer), str(N), "15", str(REPEATS), str(out)], check=True,
                               capture_output=True, text=True)
            cpp_s.append(json.loads(p.stdout)["median_s"])
            raw = np.fromfile(out, dtype=np.uint8)
            poses = raw[: N * 128].view(np.float64).reshape(N, 4, 4).copy()
            expect = raw[N * 128:].astype(bool)

            e = asimov.Engine()
            part = e.add_cylinder("part", 50, 300, 24)
            box = e.add_box("box", (400, 300, 200), static=True)
            e.set_pose(box, np.eye(4))
            hits = e.check_poses(part, poses)  # warm-up, as the peer
            assert np.array_equal(hits, expect), "Python and C++ disagree"
            times = []
            for _ in range(REPEATS):
                t0 = time.perf_counter()
                e.check_poses(part, poses)
                times.append(time.perf_counter() - t0)
            py_s.append(statistics.median(times))
    cpp, py = statistics.median(cpp_s), statistics.median(py_s)
    row = {"name": f"engine batch, {N} poses (cylinder vs box)", "ours_us": py / N * 1e6, "peer": "same loop in C++",
           "peer_us": cpp / N * 1e6, "ratio": py / cpp, "agreement": f"{N}/{N} poses",
           "contacts": int(expect.sum()), "rounds": rounds,
           "ratio_per_round": [round(a / b, 3) for a, b in zip(py_s, cpp_s)]}
    print(json.dumps(row, indent=1))
    results = pathlib.Path(__file__).parent / "results" / "python_engine.json"
    results.write_text(json.dumps([row], indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
