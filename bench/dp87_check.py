#!/usr/bin/env python3
"""Check the Prince-Dormand RK8(7)13M coefficients typed into src/sim/vi_arkode.c
(dp87_table) against the Runge-Kutta order conditions in exact rational
arithmetic: row sums = nodes, the quadrature conditions up to order 8 (7 for
the embedding) and the bushy-tree conditions b.A.c^k and b.(c * A.c^k).
Reads the numbers from the C source itself, so a typo there fails here.
(The copy of the table this was first checked against had bhat_1 with a
denominator 455176632; the order conditions put it at 455176623.)"""
import os
import re
import sys
from fractions import Fraction as F

src = open(os.path.join(os.path.dirname(__file__), "..", "src", "vi_arkode.c")).read()
body = src[src.index("static ARKodeButcherTable dp87_table(void)"):]
body = body[:body.index("\n}\n")]


def num(expr):
    expr = expr.strip()
    if "/" in expr:
        a, b = expr.split("/")
        return F(int(float(a))) / F(int(float(b)))
    return F(int(float(expr))) if float(expr) == int(float(expr)) else F(expr)


def arr(name):
    m = re.search(r"double %s\[S\] = \{(.*?)\};" % name, body, re.S)
    return [num(x) for x in m.group(1).split(",")]


S = 13
c, b, d = arr("c"), arr("b"), arr("d")
A = [[F(0)] * S for _ in range(S)]
for i, j, a in re.findall(r"\{(\d+), (\d+), ([-0-9. /]+)\}", body):
    A[int(i)][int(j)] = num(a)
worst = 0.0
for i in range(S):
    worst = max(worst, abs(float(sum(A[i]) - c[i])))
for w, p in ((b, 8), (d, 7)):
    Ac = [[sum(A[i][j] * c[j] ** k for j in range(S)) for i in range(S)] for k in range(p)]
    for k in range(p):
        worst = max(worst, abs(float(sum(w[i] * c[i] ** k for i in range(S)) - F(1, k + 1))))
    for k in range(p - 1):
        worst = max(worst, abs(float(sum(w[i] * Ac[k][i] for i in range(S)) - F(1, (k + 1) * (k + 2)))))
    for k in range(p - 2):
        worst = max(worst, abs(float(sum(w[i] * c[i] * Ac[k][i] for i in range(S)) - F(1, (k + 1) * (k + 3)))))
print("largest order-condition residual: %.2e" % worst)
sys.exit(0 if worst < 1e-16 else 1)
