#!/usr/bin/python3
"""A recording from one generated period (gen_identify_data.py output):
the period repeated PERIODS times with Gaussian noise of LEVEL times the
peak-to-peak, seed SEED; columns t,x (and v with --v).  With --a (a file
with the acceleration column a) the recording is an accelerometer's:
columns t,a, the noise LEVEL times a's peak-to-peak.
usage: noisy_recording.py IN.csv PERIODS LEVEL SEED [--v | --a] > OUT.csv"""
import sys

import numpy as np


def main():
    a = sys.argv[1:]
    withv = '--v' in a
    acc = '--a' in a
    a = [x for x in a if x not in ('--v', '--a')]
    src, periods, level, seed = a[0], int(a[1]), float(a[2]), int(a[3])
    d = np.loadtxt(src, delimiter=',', comments='#', skiprows=3)
    t, x, v = d[:, 0], d[:, 1], d[:, 2]
    if acc:
        x = d[:, 3]
    T = t[1] * len(t)
    rng = np.random.default_rng(seed)
    sig = level * (x.max() - x.min())
    print("# noisy_recording.py %s %d %g %d" % (src, periods, level, seed))
    print("t,a" if acc else "t,x,v" if withv else "t,x")
    for p in range(periods):
        noise = rng.normal(0.0, sig, len(t)) if sig > 0 else np.zeros(len(t))
        for i in range(len(t)):
            if withv:
                print("%r,%r,%r" % (t[i] + p * T, x[i] + noise[i], v[i]))
            else:
                print("%r,%r" % (t[i] + p * T, x[i] + noise[i]))


if __name__ == '__main__':
    main()
