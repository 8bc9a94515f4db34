#!/usr/bin/env python3
"""Compare two R(t) series sampled at the same times (scripts/peer_apecss.sh).

usage: compare.py LABEL R0 MAGBUBBLE_SERIES_CSV APECSS_TXT [ringdown]

Prints one row: the largest |R_mb - R_peer|/R0 over the samples, max R and min R of each
(over the samples), and for a ring-down the damped period of each (mean spacing of the
parabola-refined maxima of R) as a frequency f = 1/period. Python standard library only.
"""
import sys


def read_mb(path):
    t, r = [], []
    with open(path) as f:
        next(f)  # header t,R
        for line in f:
            a, b = line.split(",")[:2]
            t.append(float(a))
            r.append(float(b))
    return t, r


def read_peer(path):
    t, r = [], []
    with open(path) as f:
        for line in f:
            a, b = line.split()[:2]
            t.append(float(a))
            r.append(float(b))
    return t, r


def maxima(t, r):
    """Times of the local maxima, refined by the parabola through the three samples."""
    out = []
    for i in range(1, len(r) - 1):
        if r[i] > r[i - 1] and r[i] >= r[i + 1]:
            d = r[i - 1] - 2 * r[i] + r[i + 1]
            h = t[i + 1] - t[i]
            off = 0.5 * (r[i - 1] - r[i + 1]) / d if d != 0 else 0.0
            out.append(t[i] + off * h)
    return out


def frequency(t, r):
    m = maxima(t, r)
    if len(m) < 3:
        return float("nan")
    return (len(m) - 1) / (m[-1] - m[0])


def main():
    label, r0, mb_path, peer_path = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4]
    ring = len(sys.argv) > 5 and sys.argv[5] == "ringdown"
    tm, rm = read_mb(mb_path)
    tp, rp = read_peer(peer_path)
    n = min(len(tm), len(tp))
    worst = 0.0
    for i in range(n):
        if abs(tm[i] - tp[i]) > 1e-6 * (tm[1] - tm[0]):
            sys.exit(f"{label}: sample {i} at different times ({tm[i]} vs {tp[i]})")
        worst = max(worst, abs(rm[i] - rp[i]) / r0)
    row = f"{label:<24} rows {n:>6}  max|dR|/R0 {worst:.2e}  maxR/R0 {max(rm[:n]) / r0:.8f} {max(rp[:n]) / r0:.8f}  minR/R0 {min(rm[:n]) / r0:.8f} {min(rp[:n]) / r0:.8f}"
    if ring:
        fm, fp = frequency(tm[:n], rm[:n]), frequency(tp[:n], rp[:n])
        row += f"  f_ring {fm:.7e} {fp:.7e} Hz (rel {abs(fm - fp) / fp:.1e})"
    print(row)


if __name__ == "__main__":
    main()
