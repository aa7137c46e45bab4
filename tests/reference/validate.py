#!/usr/bin/env python3
"""Validation of adding_doubling.py against published / reference values."""
import math, sys
from adding_doubling import Slab

PI = math.pi
N = int(sys.argv[1]) if len(sys.argv) > 1 else 32

# (label, phase, params, w, mu0, tau, {quantity: published}, source)
REFS = [
    ("iso b=1", "iso", {}, 1.0, 1.0, 1.0,
     {"R": 0.34133, "T": 0.65867},
     "van de Hulst 1980 vol.1 Table 12 pp.258-259 (as quoted in flick tests)"),
    ("HG g=.5 a=1 b=1", "hg", {"g": 0.5}, 1.0, 1.0, 1.0,
     {"T": 0.82389},
     "van de Hulst 1980 vol.2 Table 35 p.419 (as quoted in flick tests)"),
    ("HG g=.5 a=.9 b=1", "hg", {"g": 0.5}, 0.9, 1.0, 1.0,
     {"T": 0.73909},
     "van de Hulst 1980 vol.2 Table 35 p.419 (as quoted in flick tests)"),
    ("HG g=.75 a=.9 b=2", "hg", {"g": 0.75}, 0.9, 1.0, 2.0,
     {"R": 0.09739, "T": 0.66096},
     "van de Hulst 1980 values quoted in MCML paper (Wang, Jacques, Zheng 1995, CMPB 47:131)"),
    # DISORT test problem 1 (stated 'compare to VH1 Table 12'); fluxes / pi
    ("iso a=.2 b=1/32 mu0=.1", "iso", {}, 0.2, 0.1, 0.03125,
     {"R": 0.0799451 / PI, "Td": 0.0794111 / PI}, "DISORT test 1a (VH1 Table 12)"),
    ("iso a=1 b=1/32 mu0=.1", "iso", {}, 1.0, 0.1, 0.03125,
     {"R": 0.422922 / PI, "Td": 0.420233 / PI}, "DISORT test 1b (VH1 Table 12)"),
    ("iso a=.2 b=32 mu0=.1", "iso", {}, 0.2, 0.1, 32.0,
     {"R": 0.259686 / PI}, "DISORT test 1d (VH1 Table 12)"),
    ("iso a=1 b=32 mu0=.1", "iso", {}, 1.0, 0.1, 32.0,
     {"R": 3.07390 / PI, "Td": 0.0676954 / PI}, "DISORT test 1e (VH1 Table 12)"),
    # DISORT test problem 3 (stated 'compare to VH2 Table 37'), HG g=0.75, mu0=1
    ("HG g=.75 a=1 b=1", "hg", {"g": 0.75}, 1.0, 1.0, 1.0,
     {"R": 0.247374 / PI, "Td": 1.73849 / PI}, "DISORT test 3a (VH2 Table 37)"),
    ("HG g=.75 a=1 b=8", "hg", {"g": 0.75}, 1.0, 1.0, 8.0,
     {"R": 1.59096 / PI, "Td": 1.54958 / PI}, "DISORT test 3b (VH2 Table 37)"),
]

print("N = %d per hemisphere" % N)
print("%-24s %-3s %10s %10s %10s  %s" % ("case", "q", "published", "this", "diff", "source"))
for label, ph, par, w, mu0, tau, pub, src in REFS:
    s = Slab(ph, par, nquad=N, mu0s=(mu0,))
    Rv, Tt, Td = s.fluxes(w, tau)[mu0]
    mine = {"R": Rv, "T": Tt, "Td": Td}
    for q, v in pub.items():
        print("%-24s %-3s %10.5f %10.5f %+10.1e  %s" % (label, q, v, mine[q], mine[q] - v, src))
    if w == 1.0:
        print("%-24s %-3s %10s %10.5f %+10.1e" % ("", "R+T", "1", Rv + Tt, Rv + Tt - 1))
