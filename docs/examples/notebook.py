# %% [markdown]
# # asimov from Python, cell by cell
# Run from the repository root after building (README.md):
#     PYTHONPATH=build/python python3 docs/examples/notebook.py
# Each `# %%` block is a notebook cell (Jupyter, VS Code and Spyder read this format).

# %%
import numpy as np
import asimov

print("asimov", asimov.__version__)

# %% [markdown]
# ## Run a program, read the report
# The report is the same document as `asimov run --report`; a collision is a result.

# %%
report = asimov.run("programs/demo/crash.v2", trace=True)
print(report["status"], report["collision"]["bodies"], "at t =", round(report["collision"]["time_s"], 3), "s")
trace = report["trace"]
print("checked poses:", trace["joints"].shape, "- J1 ends at",
      round(trace["joints"][-1, 0], 3), "deg")

# %% [markdown]
# ## A cell as a dict, a monitor session

# %%
cell = asimov.load_cell({
    "robot": "puma560",
    "objects": [{"name": "pillar", "box": [100, 100, 1500], "at": [500, -150, -300, 0, 0, 0]}],
})
session = asimov.Session(cell)
session.execute("POINT hover = TRANS(500, 200, 100, 0, 180, 0)")
session.execute("DO MOVE hover")
print(session.execute("WHERE"))
try:
    session.execute("DO MOVES TRANS(500, -400, 100, 0, 180, 0)")  # straight line through the pillar
except asimov.CommandError as e:
    print("stopped:", e.message)

# %% [markdown]
# ## FK / IK of any arm

# %%
puma = asimov.puma560()
q = np.array([10, -80, 100, 20, 30, 40.0])
flange = puma.fk(q)
back = puma.ik(flange, current=puma.ready, config=puma.configuration(q))
print("IK error [mm]:", np.linalg.norm(puma.fk(back)[:3, 3] - flange[:3, 3]))
generic6 = asimov.load_urdf("robots/data/generic6.urdf")
print(generic6, "flange at zero:", generic6.fk(np.zeros(6))[:3, 3])

# %% [markdown]
# ## The collision engine on its own, 10,000 poses in one call

# %%
engine = asimov.Engine()
part = engine.add_cylinder("part", 50, 300)
box = engine.add_box("box", (400, 300, 200), static=True)
engine.set_pose(box, np.eye(4))
rng = np.random.default_rng(1)
poses = np.tile(np.eye(4), (10000, 1, 1))
poses[:, :3, 3] = rng.uniform(-450, 450, (10000, 3))
hits = engine.check_poses(part, poses)
print(f"{hits.sum()} of {len(hits)} poses touch the box")
