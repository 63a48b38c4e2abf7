#!/usr/bin/env python3
"""A recording set made by another engine: MuJoCo's ellipsoid fluid model.

`omniad synth` simulates with our own model and effects; the residual
analysis must also diagnose air it did not write. This script drops and
throws a plate or an open box in MuJoCo (a free body, one box geom with
fluidshape="ellipsoid", RK4 at 1/1200 s), films it with the shared sets'
camera and writes the recording format of ../shared/docs/recording-format.md
with truth/ (states, the quasi-steady coefficients at zero spin on the
32 x 16 grid, and truth/model.toml naming MuJoCo's terms).

What MuJoCo's air holds (mujoco.readthedocs.io, computation/fluid.html;
engine_passive.c): blunt and slender drag and Kutta lift (quadratic in V:
an OmniAD C_F), angular drag, Magnus lift C_M rho Vol (omega x v), viscous
Stokes drag, and added mass's velocity terms only — force
(m_A o v) x omega, torques (m_A o v) x v and (I_A o omega) x omega —
since `mj_addedMassForces` is called without accelerations (its
-m_A dv/dt acceleration reaction is "disabled due to dependency on
qacc"). `--fluidcoef` sets MuJoCo's five coefficients (blunt, slender,
angular, Kutta, Magnus), `--wind` MuJoCo's `opt.wind`.

Usage: python3 scripts/mujoco_set.py OUT [--object plate|box] [--seed N]
         [--fluidcoef "0.5 0.25 1.5 1.0 1.0"] [--wind x,y,z] [--noise PX]
Needs `pip install mujoco numpy`. A measurement tool: no test depends on it.
"""
import argparse
import math
import os
import random

import mujoco
import numpy as np

FPS = 60
SUBSTEPS = 20
CAMERA = dict(width=720, height=1280, fx=1100.0, fy=1100.0, cx=359.5, cy=639.5,
              distortion=[-0.05, 0.01, 0.0005, -0.0003, 0.0],
              rotation=[[1, 0, 0], [0, 0, -1], [0, 1, 0]], translation=[0.0, 3.5, 7.0])

# The shared sets' objects: plate 30 x 50 x 2 cm, 48 g (uniform); open box
# 30 x 40 x 20 cm, 40 g (a box-kite cell's frame and covering).
OBJECTS = {
    "plate": dict(half=(0.15, 0.25, 0.01), mass=0.048,
                  inertia=(0.0010016, 0.0003616, 0.00136), pole=(0, 0, 1),
                  markers=[(sx * 0.135, sy * 0.225, sz * 0.01)
                           for sz in (1, -1) for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1))]),
    "box": dict(half=(0.15, 0.2, 0.1), mass=0.04,
                inertia=(0.000826666667, 0.000833333333, 0.00107333333), pole=(0, 1, 0),
                markers=[(sx * 0.15, sy * 0.18, sz * 0.1)
                         for sy in (1, -1) for sx, sz in ((1, 1), (-1, 1), (-1, -1), (1, -1))]),
}


def model_xml(obj, fluidcoef, wind):
    hx, hy, hz = obj["half"]
    ix, iy, iz = obj["inertia"]
    return f"""<mujoco>
  <compiler inertiafromgeom="false"/>
  <option timestep="{1.0 / (FPS * SUBSTEPS)}" integrator="RK4" density="1.2"
          viscosity="1.8e-5" gravity="0 0 -9.81" wind="{wind[0]} {wind[1]} {wind[2]}">
    <flag contact="disable"/>
  </option>
  <worldbody>
    <body name="obj" pos="0 0 5">
      <freejoint/>
      <inertial pos="0 0 0" mass="{obj['mass']}" diaginertia="{ix} {iy} {iz}"/>
      <geom type="box" size="{hx} {hy} {hz}" mass="0" fluidshape="ellipsoid"
            fluidcoef="{fluidcoef}"/>
    </body>
  </worldbody>
</mujoco>"""


def quat_to_matrix(q):
    m = np.zeros(9)
    mujoco.mju_quat2Mat(m, np.asarray(q, dtype=float))
    return m.reshape(3, 3)


def random_quat(rng):
    q = np.array([rng.gauss(0, 1) for _ in range(4)])
    return q / np.linalg.norm(q)


def simulate(m, d, pos, quat, vel, omega, max_t):
    """States at every frame until the centre falls below 8 cm."""
    mujoco.mj_resetData(m, d)
    d.qpos[:3], d.qpos[3:7] = pos, quat
    d.qvel[:3], d.qvel[3:6] = vel, omega
    mujoco.mj_forward(m, d)
    rows = []
    for frame in range(int(max_t * FPS) + 1):
        rows.append([frame / FPS, *d.qpos[:7], *d.qvel[:6]])
        if d.qpos[2] < 0.08:
            break
        for _ in range(SUBSTEPS):
            mujoco.mj_step(m, d)
    return rows


def project(p_world):
    c = CAMERA
    r, t = np.array(c["rotation"], float), np.array(c["translation"])
    x, y, z = r @ p_world + t
    if z <= 0.1:
        return None
    k1, k2, p1, p2, k3 = c["distortion"]
    xn, yn = x / z, y / z
    r2 = xn * xn + yn * yn
    radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 ** 3
    xd = xn * radial + 2 * p1 * xn * yn + p2 * (r2 + 2 * xn * xn)
    yd = yn * radial + p1 * (r2 + 2 * yn * yn) + 2 * p2 * xn * yn
    u, v = c["fx"] * xd + c["cx"], c["fy"] * yd + c["cy"]
    if not (0 <= u <= c["width"] - 1 and 0 <= v <= c["height"] - 1):
        return None
    return u, v


def marker_rows(obj, states, rng, noise, drop):
    """A marker is seen when the face (plate) or corner (box) it sits on
    looks towards the camera; 2 % are lost; 0.7 px Gaussian noise."""
    r, t = np.array(CAMERA["rotation"], float), np.array(CAMERA["translation"])
    centre = -r.T @ t
    out = []
    for frame, s in enumerate(states):
        y, rot = np.array(s[1:4]), quat_to_matrix(s[4:8])
        for i, mk in enumerate(obj["markers"]):
            mk = np.array(mk)
            normal = np.sign(mk) if obj is OBJECTS["box"] else np.array([0, 0, np.sign(mk[2])])
            p = y + rot @ mk
            if (rot @ normal) @ (centre - p) <= 0 or rng.random() < drop:
                continue
            uv = project(p)
            if uv is None:
                continue
            out.append(f"{frame},m{i},{uv[0] + rng.gauss(0, noise):.3f},{uv[1] + rng.gauss(0, noise):.3f}")
    return out


def coefficients(m, d, obj):
    """C_F, C_T at |V| = 1 m/s, zero spin, no gravity's part, on the grid
    the shared sets use (body frame = world frame at the identity)."""
    lref = 2 * math.sqrt(sum(h * h for h in obj["half"]))
    rows = []
    wind = m.opt.wind.copy()
    m.opt.wind[:] = 0
    for lat in range(16):
        for lon in range(32):
            th, ph = (lat + 0.5) * math.pi / 16, lon * 2 * math.pi / 32
            e = np.array([math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)])
            mujoco.mj_resetData(m, d)
            d.qpos[3:7] = [1, 0, 0, 0]
            d.qvel[:3] = e
            mujoco.mj_forward(m, d)
            f, tq = d.qfrc_passive[:3], d.qfrc_passive[3:6]
            q = 0.5 * 1.2
            rows.append([*e, *(f / (q * lref ** 2)), *(tq / (q * lref ** 3))])
    m.opt.wind[:] = wind
    return rows, lref


def fmt(v):
    return ", ".join(f"{x:.9g}" for x in v)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--object", choices=OBJECTS, default="plate")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--fluidcoef", default="0.5 0.25 1.5 1.0 1.0")
    ap.add_argument("--wind", default="0,0,0")
    ap.add_argument("--noise", type=float, default=0.7)
    ap.add_argument("--drops", type=int, default=8)
    ap.add_argument("--spins", type=int, default=5)
    a = ap.parse_args()
    wind = [float(x) for x in a.wind.split(",")]
    obj = OBJECTS[a.object]
    rng = random.Random(a.seed)
    m = mujoco.MjModel.from_xml_string(model_xml(obj, a.fluidcoef, wind))
    d = mujoco.MjData(m)
    os.makedirs(os.path.join(a.out, "truth"), exist_ok=True)
    takes = []
    for i in range(a.drops + a.spins):
        drop = i < a.drops
        name = f"{'drop' if drop else 'spin'}-{i + 1:02d}"
        if drop:
            pos = [rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(5.6, 6.4)]
            vel = [rng.gauss(0, 0.2), rng.gauss(0, 0.2), rng.gauss(-0.3, 0.2)]
            omega = [rng.gauss(0, 1.0) for _ in range(3)]
        else:
            pos = [rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), 1.0]
            vel = [rng.gauss(0, 0.3), rng.gauss(0, 0.3), rng.uniform(3.4, 4.2)]
            axis = np.array([rng.gauss(0, 1) for _ in range(3)])
            omega = list(axis / np.linalg.norm(axis) * rng.uniform(10, 16))
        quat = random_quat(rng)
        states = simulate(m, d, pos, quat, vel, omega, 6.0)
        with open(os.path.join(a.out, "truth", name + ".csv"), "w") as f:
            f.write("t,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n")
            f.writelines(",".join(f"{x:.7g}" for x in s) + "\n" for s in states)
        with open(os.path.join(a.out, name + ".csv"), "w") as f:
            f.write("frame,marker,u,v\n")
            f.writelines(r + "\n" for r in marker_rows(obj, states, rng, a.noise, 0.02))
        guess_p = [x + rng.gauss(0, 0.04) for x in states[0][1:4]]
        guess_q = np.array(states[0][4:8]) + np.array([rng.gauss(0, 0.03) for _ in range(4)])
        takes.append((name, "drop" if drop else "spin", guess_p, guess_q / np.linalg.norm(guess_q)))
    rows, lref = coefficients(m, d, obj)
    with open(os.path.join(a.out, "truth", "coefficients.csv"), "w") as f:
        f.write("ex,ey,ez,cfx,cfy,cfz,ctx,cty,ctz\n")
        f.writelines(",".join(f"{x:.7g}" for x in r) + "\n" for r in rows)
    with open(os.path.join(a.out, "truth", "model.toml"), "w") as f:
        f.write(f'engine = "mujoco"\nversion = "{mujoco.__version__}"\n[effects]\n'
                f'engine = "mujoco"\nfluidcoef = "{a.fluidcoef}"\nwind = [{fmt(wind)}]\n'
                'added_mass = "velocity terms only (no acceleration reaction)"\n')
    ix, iy, iz = obj["inertia"]
    lines = ['format = "omniad-recording/1"', "", "[world]", "gravity = [0, 0, -9.81]",
             "air_density = 1.2", "air_viscosity = 1.8e-05", "", "[object]",
             f'name = "{a.object}"', f"mass = {obj['mass']}",
             f"inertia = [[{ix}, 0, 0], [0, {iy}, 0], [0, 0, {iz}]]",
             f"reference_length = {lref:.9g}", f"pole = [{fmt(obj['pole'])}]", "",
             "[object.markers]"]
    lines += [f"m{i} = [{fmt(mk)}]" for i, mk in enumerate(obj["markers"])]
    c = CAMERA
    lines += ["", "[camera]", f"width = {c['width']}", f"height = {c['height']}", f"fps = {FPS}",
              f"fx = {c['fx']}", f"fy = {c['fy']}", f"cx = {c['cx']}", f"cy = {c['cy']}",
              f"distortion = [{fmt(c['distortion'])}]",
              "rotation = [" + ", ".join(f"[{fmt(r)}]" for r in c["rotation"]) + "]",
              f"translation = [{fmt(c['translation'])}]", f"pixel_noise = {a.noise}"]
    for name, kind, p, q in takes:
        lines += ["", "[[take]]", f'name = "{name}"', f'kind = "{kind}"', f'markers = "{name}.csv"',
                  f"initial_position = [{fmt(p)}]", f"initial_orientation = [{fmt(q)}]"]
    with open(os.path.join(a.out, "recording.toml"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
