#!/usr/bin/env python3
"""How wrong a reconstruction's dV/dt is, against a synthetic set's truth.

Added mass's regressor is dV/dt, the rate of the body-frame velocity
V = R^T v, made by the same central difference of the smoothed states as
eq. (9)'s force. If its error e is *classical* (uncorrelated with the true
rate a) least squares attenuates M_a; if it is *Berkson* (uncorrelated
with the estimate a + e, a well-calibrated smoother's) it does not. This
script prints, per body axis, the spread of the true rate and of the
error, corr(e, a) and corr(e, a + e), and the percentiles of |e|
(BENCHMARKS.md, stop 27).

Usage:
  omniad synth SET --object box --effect added_mass=1.0 --seed 1 --noise 0.7
  omniad reconstruct SET -o REC --iterations 1
  python3 scripts/rate_error.py SET REC
Needs numpy. A measurement tool: no test depends on it.
"""
import csv
import glob
import os
import sys

import numpy as np


def load(path):
    """Rows t,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz (header skipped)."""
    with open(path) as f:
        rows = list(csv.reader(f))[1:]
    return np.array([[float(x) for x in r] for r in rows])


def rotation(q):
    """Body -> world rotation matrix of the unit quaternion (w, x, y, z)."""
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def rates(states):
    """Central-difference rate of V = R^T v at the interior epochs, m/s^2."""
    t = states[:, 0]
    body = np.array([rotation(s[4:8]).T @ s[8:11] for s in states])
    return (body[2:] - body[:-2]) / (t[2:] - t[:-2])[:, None]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    set_dir, rec_dir = sys.argv[1], sys.argv[2]
    true_rates, errors = [], []
    paths = sorted(glob.glob(os.path.join(rec_dir, "*.csv")))
    if not paths:
        sys.exit(f"rate_error: no <take>.csv in {rec_dir}")
    for path in paths:
        truth_path = os.path.join(set_dir, "truth", os.path.basename(path))
        if not os.path.exists(truth_path):
            sys.exit(f"rate_error: no truth for {path}: {truth_path} is missing")
        truth, rec = load(truth_path), load(path)
        # The truth's state at each reconstructed epoch's time (a take may
        # have fewer epochs than the truth has frames), so that both rates
        # difference the same epochs.
        # (`omniad reconstruct` writes t to the microsecond: nearest.)
        at = np.abs(truth[:, 0][:, None] - rec[:, 0][None, :]).argmin(axis=0)
        if len(rec) < 3 or np.abs(truth[at, 0] - rec[:, 0]).max() > 1e-5:
            sys.exit(f"rate_error: {path}: its times are not the truth's ({truth_path})")
        a, seen = rates(truth[at]), rates(rec)
        ok = np.all(np.isfinite(seen), axis=1)
        true_rates.append(a[ok])
        errors.append(seen[ok] - a[ok])
    a, e = np.vstack(true_rates), np.vstack(errors)
    # The error has a heavy tail (a few frames far beyond the rest), so
    # its robust spread (1.4826 x the median absolute deviation) is
    # printed beside the standard deviation.
    mad = 1.4826 * np.median(np.abs(e - np.median(e, axis=0)), axis=0)
    for i, axis in enumerate("xyz"):
        print(
            f"{axis}: sd(a) {a[:, i].std():.3f}  sd(e) {e[:, i].std():.3f} "
            f"(robust {mad[i]:.3f}) m/s^2  "
            f"corr(e, a) {np.corrcoef(e[:, i], a[:, i])[0, 1]:+.3f}  "
            f"corr(e, a+e) {np.corrcoef(e[:, i], a[:, i] + e[:, i])[0, 1]:+.3f}"
        )
    p = np.percentile(np.linalg.norm(e, axis=1), [50, 90, 99])
    q = np.percentile(np.linalg.norm(a, axis=1), [50, 90, 99])
    print(f"|e| 50/90/99 %: {p.round(2)} m/s^2; |a|: {q.round(2)} m/s^2; {len(a)} frames")


if __name__ == "__main__":
    main()
