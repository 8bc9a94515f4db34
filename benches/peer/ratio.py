#!/usr/bin/env python3
"""Speed ratio at equal accuracy: magbubble accuracy.csv vs the peer's CSV (see run.sh).

For each target error e* in the range both reached, the wall time of each solver at e* is
interpolated log-log along its ladder (monotone part); ratio = peer time / magbubble time.
Usage: ratio.py MAGBUBBLE_ACCURACY.csv PEER.csv
"""
import csv
import math
import sys

def curve(points):
    pts = sorted((e, w) for e, w in points if math.isfinite(e) and e > 0 and w > 0)
    return pts


def time_at(pts, target):
    # pts sorted by error ascending; log-log interpolation of wall time at the target error
    for (e1, w1), (e2, w2) in zip(pts, pts[1:]):
        if e1 <= target <= e2 and e2 > e1:
            s = (math.log(target) - math.log(e1)) / (math.log(e2) - math.log(e1))
            return math.exp(math.log(w1) + s * (math.log(w2) - math.log(w1)))
    return None


def main():
    mag, peer = {}, {}
    with open(sys.argv[1]) as f:
        for r in csv.DictReader(f):
            mag.setdefault(r["method"], []).append((float(r["error"]), float(r["wall_seconds"])))
    with open(sys.argv[2]) as f:
        for r in csv.DictReader(f):
            peer.setdefault(r["method"], []).append((float(r["error"]), float(r["wall_seconds"])))
    pairs = [("dopri5", "RK45"), ("radau5", "Radau"), ("radau5", "LSODA"), ("dop853", "DOP853"), ("dopri5", "LSODA")]
    print(f"{'magbubble':>10} {'scipy':>7} {'error':>9} {'t_mag s':>10} {'t_scipy s':>10} {'ratio':>8}")
    for m, p in pairs:
        a, b = curve(mag.get(m, [])), curve(peer.get(p, []))
        for target in (1e-4, 1e-6, 1e-8):
            ta, tb = time_at(a, target), time_at(b, target)
            if ta and tb:
                print(f"{m:>10} {p:>7} {target:>9.0e} {ta:>10.2e} {tb:>10.2e} {tb / ta:>8.0f}")


if __name__ == "__main__":
    main()
