"""Best-of-N in-process wall time (simulate --json wall_seconds) per RHS call on the Fig. 8
scenes: an old and a new rocklab binary and the new one computing the rotation alone, in turn.

Usage: scripts/ns-per-rhs.py OLD_BIN NEW_BIN [N]
"""
import json, subprocess, sys
OLD, NEW = sys.argv[1], sys.argv[2]
M = "--device mechanistic --sigma 0.5 --clutch-frequency-ratio 25 --cbar 1".split()
base = "simulate --p 2 --alpha 10deg --amplitude-alpha 1.5 --frequency-ratio 4 --duration 10 --json".split()
N = int(sys.argv[3]) if len(sys.argv) > 3 else 25
print("| scene | rtol | RHS evals | steps | old ns/RHS | new ns/RHS | new, rotation only ns/RHS | old/new |")
print("|---|---|---|---|---|---|---|---|")
for name, extra in [("bare", []), ("mechanistic", M)]:
    for rtol in ["1e-4", "1e-6", "1e-8"]:
        variants = {"old": [OLD], "new": [NEW], "rot": [NEW, "--quantities", "peak_rotation_ratio"]}
        best = {k: float("inf") for k in variants}
        info = None
        for _ in range(N):
            for k, v in variants.items():
                cmd = v[:1] + base + ["--rtol", rtol] + extra + v[1:]
                d = json.loads(subprocess.run(cmd, capture_output=True, text=True).stdout)
                best[k] = min(best[k], d["wall_seconds"])
                info = (d["rhs_evals"], d["steps"])
        r = info[0]
        ns = {k: best[k] / r * 1e9 for k in best}
        print(f"| {name} | {rtol} | {r} | {info[1]} | {ns['old']:.0f} | {ns['new']:.0f} | {ns['rot']:.0f} | {ns['old']/ns['new']:.2f} |")
