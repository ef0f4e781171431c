#!/usr/bin/env python3
"""Instructions per RHS call on a Fig. 8 scene at rtol 1e-8, counted by callgrind (repeatable on
a loaded machine): all-in (the whole scene, `sim::run_sampled` inclusive) and in the RHS calls
themselves (`OdeSystem::rhs` of the rocking model, inclusive of its sines and cosines: every call
rhs_evals counts, from the stages, the dense output's extra stages and the restarts).

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
# The right-hand side is a function of its own (not inlined into the stage loops): its inclusive
# cost, on the line that names the binary, covers every call.
stage = max((ir(l) for l in annotate()
             if re.search(r"OdeSystem<_> for rocklab::model::shell::Rocking<B>>::rhs \[", l)),
            default=0)
if stage == 0:
    sys.exit("no OdeSystem::rhs of the rocking model in the profile (inlined into its callers?)")
print(f"{scene} {' '.join(extra)}: {rhs} RHS calls, {total / rhs:.0f} Ir/RHS all-in, "
      f"{stage / rhs:.0f} Ir/RHS in the RHS calls, ratio {total / stage:.1f}")
