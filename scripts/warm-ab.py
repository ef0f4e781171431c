#!/usr/bin/env python3
"""Two rocklab builds, warm, on the picks of scripts/peer/run.sh (the Fig. 8 bare block at rtol
3e-5 / 3e-7 / 1e-9 and the mechanistic one at 3e-6 / 3e-8 / 1e-9, the tolerances at which each
meets the peak errors 1e-4 / 1e-6 / 1e-8), alternating A and B pick by pick so that the
machine's slow spells hit both alike, pinned to CPU 1. A time is the fastest over ROUNDS of
`simulate … --repeat REPEAT` (itself the fastest of REPEAT in-process runs). Each row says
whether both builds gave the same RHS calls and peak to the last bit.

    scripts/warm-ab.py BIN_A BIN_B [ROUNDS=5] [REPEAT=51] [SCENE_FILTER: bare | mech]
"""
import json, subprocess, sys
A, B = sys.argv[1], sys.argv[2]
R = int(sys.argv[3]) if len(sys.argv) > 3 else 5
REP = sys.argv[4] if len(sys.argv) > 4 else "51"
base = "simulate --p 2 --alpha 10deg --amplitude-alpha 1.5 --frequency-ratio 4 --duration 10 --json --quantities peak_rotation_ratio".split()
mech = "--device mechanistic --sigma 0.5 --clutch-frequency-ratio 25 --cbar 1".split()
picks = [("bare", "3e-5"), ("bare", "3e-7"), ("bare", "1e-9"), ("mech", "3e-6"), ("mech", "3e-8"), ("mech", "1e-9")]
only = sys.argv[5] if len(sys.argv) > 5 else ""
picks = [p for p in picks if only in p[0]]
best, info = {}, {}
for _ in range(R):
    for scene, rtol in picks:
        for name, exe in (("A", A), ("B", B)):
            args = ["taskset", "-c", "1", exe] + base + (mech if scene == "mech" else []) + ["--rtol", rtol, "--repeat", REP]
            d = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
            k = (name, scene, rtol)
            best[k] = min(best.get(k, 1e9), d["wall_seconds"] * 1e6)
            info[k] = (d["rhs_evals"], d["peak_rotation_ratio"])
prod = 1.0
for scene, rtol in picks:
    a, b = best[("A", scene, rtol)], best[("B", scene, rtol)]
    ia, ib = info[("A", scene, rtol)], info[("B", scene, rtol)]
    same = "same" if ia == ib else f"DIFF rhs {ia[0]}->{ib[0]} peak {ia[1]!r}->{ib[1]!r}"
    print(f"{scene} {rtol}: A {a:8.2f} us ({a*1e3/ia[0]:.1f} ns/RHS)  B {b:8.2f} us ({b*1e3/ib[0]:.1f} ns/RHS)  A/B {a/b:.3f}  {same}")
