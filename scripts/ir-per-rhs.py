#!/usr/bin/env python3
"""Instructions per RHS call on a Fig. 8 scene at rtol 1e-8, counted by callgrind (repeatable on
a loaded machine): all-in (the whole scene, `sim::run_sampled` inclusive) and in the
RK stages' RHS calls (the RHS evaluations the stepping loop (`sim::drive`, or `run_sampled` where it is inlined, and `dop853_stage`) make: `rhs_slice`,
or the kinematics' `sincos` plus `rhs_kin`, inclusive).

Usage: scripts/ir-per-rhs.py BIN bare|mechanistic [extra simulate flags…]
"""
import json, re, subprocess, sys

binary, scene, extra = sys.argv[1], sys.argv[2], sys.argv[3:]
args = "simulate --p 2 --alpha 10deg --amplitude-alpha 1.5 --frequency-ratio 4 --duration 10 --rtol 1e-8 --json".split()
if scene == "mechanistic":
    args += "--device mechanistic --sigma 0.5 --clutch-frequency-ratio 25 --cbar 1".split()
args += extra
rhs = json.loads(subprocess.run([binary] + args, capture_output=True, text=True).stdout)["rhs_evals"]
out = "/tmp/rocklab-ir.callgrind"
subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", binary] + args,
               capture_output=True, check=True)
annotate = lambda *o: subprocess.run(["callgrind_annotate", "--inclusive=yes", *o, out],
                                    capture_output=True, text=True, cwd="/").stdout.split("\n")
ir = lambda line: int(line.split()[0].replace(",", ""))
total = max(ir(l) for l in annotate() if re.search(r"sim/mod.rs:rocklab::sim::run_sampled \[", l))
lines = annotate("--tree=caller")
stage = 0
for i, line in enumerate(lines):
    if re.search(r"\*\s+.*(rhs_slice|rhs_kin|__sincos_fma) \[", line):
        j = i - 1
        while j >= 0 and re.match(r"^\s*[\d,]+ .*<", lines[j]):
            if re.search(r"(sim::(run_sampled|drive)|Integrator<_>::dop853_stage) \(", lines[j]):
                stage += ir(lines[j])
            j -= 1
print(f"{scene} {' '.join(extra)}: {rhs} RHS calls, {total / rhs:.0f} Ir/RHS all-in, "
      f"{stage / rhs:.0f} Ir/RHS in the stages' RHS calls, ratio {total / stage:.1f}")
