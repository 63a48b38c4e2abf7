#!/usr/bin/env python3
"""How much of `omniad residual`'s held-out force RMS no model can remove,
on a synthetic set with its truth.

The residual of a frame is the measured force F* (eq. 9: M R^T (dv/dt - g)
from the reconstructed states) minus the held-out model's force. The same
eq. 9 on the truth's states gives F*_true; their difference is the
target's own noise (the reconstruction's), which a perfect model would
still leave. This script splits each model's residual RMS into that noise
and the rest, `residual - noise` (the model's own error against the
true target). A model whose own error were zero would still have the
acceptance's ratio after/before (issue 15) at noise_after /
residual_before (BENCHMARKS.md, stop 29).

Usage:
  omniad synth SET --object box --effect added_mass=1.0 --seed 1
  omniad residual SET --plots PLOTS
  python3 scripts/target_noise.py SET PLOTS/residual-frames.csv
Needs numpy. A measurement tool: no test depends on it.
"""
import csv
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rate_error import load, rotation  # noqa: E402


def recording_constants(set_dir):
    """(mass, gravity) from recording.toml (the two lines this needs)."""
    mass, gravity = None, None
    with open(os.path.join(set_dir, "recording.toml")) as f:
        for line in f:
            key, _, value = line.partition("=")
            key = key.strip()
            if key == "mass" and mass is None:
                mass = float(value)
            elif key == "gravity" and gravity is None:
                gravity = np.array([float(x) for x in value.strip().strip("[]").split(",")])
    if mass is None or gravity is None:
        sys.exit(f"target_noise: no object mass or world gravity in {set_dir}/recording.toml")
    return mass, gravity


def true_force(truth, t, mass, gravity):
    """Eq. 9 on the truth's states at the epoch at time t (central
    difference), body frame, N; None at a take's first or last epoch
    (no central difference there). Raises ValueError when the truth has
    no epoch at t (a table of another set)."""
    k = int(np.abs(truth[:, 0] - t).argmin())
    # `omniad residual` writes t to the microsecond.
    if abs(truth[k, 0] - t) > 1e-5:
        raise ValueError(f"no truth epoch at t = {t} s (nearest {truth[k, 0]} s)")
    if k == 0 or k == len(truth) - 1:
        return None
    rate = (truth[k + 1, 8:11] - truth[k - 1, 8:11]) / (truth[k + 1, 0] - truth[k - 1, 0])
    return mass * rotation(truth[k, 4:8]).T @ (rate - gravity)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    set_dir, table = sys.argv[1], sys.argv[2]
    mass, gravity = recording_constants(set_dir)
    truths, split, ends = {}, {}, 0
    columns = {"model", "take", "t", "fx", "fy", "fz", "rx", "ry", "rz"}
    with open(table) as f:
        reader = csv.DictReader(f)
        missing = columns - set(reader.fieldnames or [])
        if missing:
            sys.exit(f"target_noise: {table} lacks the columns {sorted(missing)} "
                     "(it should be omniad residual's residual-frames.csv)")
        for line, row in enumerate(reader, start=2):
            take = row["take"]
            if take not in truths:
                path = os.path.join(set_dir, "truth", take + ".csv")
                if not os.path.exists(path):
                    sys.exit(f"target_noise: no truth for take {take}: {path} is missing")
                truths[take] = load(path)
            try:
                f_true = true_force(truths[take], float(row["t"]), mass, gravity)
            except ValueError as e:
                sys.exit(f"target_noise: {table} line {line}, take {take}: {e}; "
                         f"is the table of {set_dir}?")
            if f_true is None:
                ends += 1
                continue
            measured = np.array([float(row[c]) for c in ("fx", "fy", "fz")])
            residual = np.array([float(row[c]) for c in ("rx", "ry", "rz")])
            split.setdefault(row["model"], []).append((measured - f_true, residual))
    if not split:
        sys.exit(f"target_noise: {table} has no frame inside a take")
    if ends:
        print(f"({ends} rows at a take's first or last epoch left out: no central difference there)")
    rms = {}
    for model, pairs in split.items():
        noise = np.array([p[0] for p in pairs])
        residual = np.array([p[1] for p in pairs])
        r = [np.sqrt((x ** 2).sum(axis=1).mean()) for x in (residual, noise, residual - noise)]
        rms[model] = r
        print(f"{model}: {len(pairs)} frames; residual RMS {r[0]:.4f} N = target noise "
              f"{r[1]:.4f} N + the model's own error {r[2]:.4f} N (RMS each)")
    # `base` is the report's baseline (the base model on the frames the
    # extended model is scored on); `first_round` the base model on the
    # first round's states (tables written before stop 30 call that one
    # `base` and have no `first_round` rows).
    for before in ("base", "first_round"):
        if before in rms and "extended" in rms:
            b, e = rms[before], rms["extended"]
            print(f"ratio after/{before}: measured {e[0] / b[0]:.3f}; the models' own errors "
                  f"{e[2] / b[2]:.3f}; an extended model with no error of its own would give "
                  f"{e[1] / b[0]:.3f} (its target noise over the {before} residual)")


if __name__ == "__main__":
    main()
