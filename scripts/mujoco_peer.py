#!/usr/bin/env python3
"""The peer of `omniad bench`: MuJoCo's ellipsoid fluid model, many light
bodies falling through air, body-steps per second on one thread.

1,000 free 30 x 50 x 2 cm, 48 g plates (box geoms, fluidshape="ellipsoid",
air density 1.2 kg/m^3, viscosity 1.8e-5), contacts off, RK4 at dt = 1/240 s.
Prints one JSON object: body_steps_per_second (RK4, the figure compared),
euler_body_steps_per_second (the same plates with MuJoCo's default
semi-implicit Euler, for reference: one force evaluation per step instead of
four), bodies, steps, version.
Usage: python3 scripts/mujoco_peer.py [--quick] [--bodies N]
"""
import argparse
import json
import math
import time

import mujoco


def model_xml(bodies, integrator="RK4"):
    plates = []
    for i in range(bodies):
        x, y = math.sin(i), math.cos(i)
        plates.append(
            f'<body pos="{x:.4f} {y:.4f} 100"><freejoint/>'
            f'<geom type="box" size="0.15 0.25 0.01" mass="0.048" '
            f'fluidshape="ellipsoid"/></body>'
        )
    return f"""<mujoco>
  <option timestep="{1.0 / 240.0}" integrator="{integrator}" density="1.2" viscosity="1.8e-5">
    <flag contact="disable"/>
  </option>
  <worldbody>{''.join(plates)}</worldbody>
</mujoco>"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--bodies", type=int, default=1000)
    a = ap.parse_args()
    steps = 40 if a.quick else 120
    runs = 3 if a.quick else 5
    rk4 = rate(a.bodies, "RK4", steps, runs)
    euler = rate(a.bodies, "Euler", steps, runs)
    print(json.dumps({
        "body_steps_per_second": rk4,
        "euler_body_steps_per_second": euler,
        "bodies": a.bodies,
        "steps": steps,
        "version": mujoco.__version__,
    }))


def rate(bodies, integrator, steps, runs):
    """Body-steps per second: the best of `runs` runs of `steps` steps."""
    m = mujoco.MjModel.from_xml_string(model_xml(bodies, integrator))
    d = mujoco.MjData(m)
    for i in range(bodies):
        d.qvel[6 * i + 3] = 0.3 * math.cos(i)
        d.qvel[6 * i + 4] = 0.2
    mujoco.mj_step(m, d, 10)  # warm up
    best = float("inf")
    for _ in range(runs):
        t = time.perf_counter()
        mujoco.mj_step(m, d, steps)
        best = min(best, time.perf_counter() - t)
    return bodies * steps / best


if __name__ == "__main__":
    main()
