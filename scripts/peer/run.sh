#!/usr/bin/env bash
# rocklab against the compiled DOP853 peer (scripts/peer/dop853.c, scipy's DOP853 in C) at equal
# peak error on the Fig. 8 bare and mechanistic scenes, warm against warm, side by side.
#
#   scripts/peer/run.sh [REPEATS] [ROUNDS]
#
# Builds the peer with `gcc -O2 -march=x86-64-v2` (the level rocklab is built for, .cargo/config.toml)
# and rocklab with `cargo build --release` (or takes the binary
# in $ROCKLAB). For every tolerance of $RTOLS and each scene, each round runs the peer (fastest
# of REPEATS in-process runs) and then `rocklab simulate … --repeat REPEATS` (its wall_seconds:
# the fastest of REPEATS in-process runs), so load on the machine hits both alike; a time is the
# fastest over ROUNDS (default 3). Both compute the peak rotation only (rocklab with
# `--quantities peak_rotation_ratio`). The error is |θmax/α − reference| / reference against
# rocklab's rtol 1e-12 run (the peer's own rtol 1e-12 run is printed beside it). For each target
# error (1e-4, 1e-6, 1e-8) each side takes its loosest tolerance that meets it; the table gives
# RHS calls, time, ns per RHS call all-in and the ratio peer time / rocklab time (> 1: rocklab
# faster), then the geometric mean of the ratios per scene, and the right-hand side alone (ns
# per call) of the peer: calls independent of each other (throughput, what the processor
# overlaps) and calls each waiting on the last (latency, what a Runge-Kutta stage chain pays).
#
# ROCKLAB_FLAGS adds flags to rocklab's timed runs only (not to its reference), e.g.
# ROCKLAB_FLAGS=--stop-when-settled: rocklab then ends a scene once no peak can change (the
# default of every study), while the peer always integrates the whole 10 s.
#
# Both sides' timed runs are pinned to CPU $CPU (default 0; CPU= to not pin): unpinned, a
# process here ran either ~21 or ~29 µs for the same peer scene, whole runs at a time.
set -euo pipefail
cd "$(dirname "$0")/../.."

REPEATS=${1:-21}
ROUNDS=${2:-3}
RTOLS=${RTOLS:-1e-3 3e-4 1e-4 3e-5 1e-5 3e-6 1e-6 3e-7 1e-7 3e-8 1e-8 3e-9 1e-9 3e-10 1e-10 1e-11}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

gcc -O2 -march=x86-64-v2 -o "$WORK/peer" scripts/peer/dop853.c -lm
if [[ -z "${ROCKLAB:-}" ]]; then
    cargo build --release --quiet --bin rocklab
    ROCKLAB=target/release/rocklab
fi
read -r -a FLAGS <<<"${ROCKLAB_FLAGS:-}"
PIN=()
[[ -n "${CPU-0}" ]] && command -v taskset >/dev/null && PIN=(taskset -c "${CPU-0}")
echo "rocklab: $ROCKLAB ($(git rev-parse --short HEAD)$(git diff --quiet || echo '+dirty')) ${ROCKLAB_FLAGS:-}; peer: gcc -O2 -march=x86-64-v2 $(gcc -dumpfullversion); load: $(cut -d' ' -f1-3 /proc/loadavg)" >&2

BASE=(simulate --p 2 --alpha 10deg --amplitude-alpha 1.5 --frequency-ratio 4 --duration 10 --json)
MECH=(--device mechanistic --sigma 0.5 --clutch-frequency-ratio 25 --cbar 1)
for scene in bare mechanistic; do
    extra=(); [[ $scene == mechanistic ]] && extra=("${MECH[@]}")
    "$ROCKLAB" "${BASE[@]}" "${extra[@]}" --rtol 1e-12 --quantities peak_rotation_ratio \
        >"$WORK/ref.$scene.json"
    "$WORK/peer" "$scene" 1 1e-12 | tail -1 >"$WORK/peerref.$scene"
    for round in $(seq "$ROUNDS"); do
        for rtol in $RTOLS; do
            "${PIN[@]}" "$WORK/peer" "$scene" "$REPEATS" "$rtol" | tail -1 >>"$WORK/peer.$scene"
            "${PIN[@]}" "$ROCKLAB" "${BASE[@]}" "${extra[@]}" "${FLAGS[@]}" --rtol "$rtol" \
                --quantities peak_rotation_ratio --repeat "$REPEATS" >>"$WORK/rocklab.$scene"
        done
    done
    "${PIN[@]}" "$WORK/peer" rhs "$scene" >"$WORK/rhs.$scene"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >&2

python3 - "$WORK" <<'EOF'
import json, math, sys
work = sys.argv[1]
print("| scene | target error | peer rtol | peer RHS | peer µs | peer ns/RHS | rocklab rtol | rocklab method | rocklab RHS | rocklab µs | rocklab ns/RHS | peer/rocklab time |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
notes = []
for scene in ("bare", "mechanistic"):
    ref = json.load(open(f"{work}/ref.{scene}.json"))["peak_rotation_ratio"]
    peer_ref = float(open(f"{work}/peerref.{scene}").read().split()[5])
    notes.append(f"{scene}: reference θmax/α {ref!r} (rocklab rtol 1e-12); the peer's at rtol 1e-12 "
                 f"differs by {abs(peer_ref - ref) / ref:.1e}")
    peer, rock = {}, {}
    for line in open(f"{work}/peer.{scene}"):
        rtol, rhs, steps, rej, ev, peak, fast, med = line.split()
        key = float(rtol)
        err = abs(float(peak) - ref) / ref
        prev = peer.get(key)
        peer[key] = (err, int(rhs), min(float(fast), prev[2]) if prev else float(fast))
    for line in open(f"{work}/rocklab.{scene}"):
        d = json.loads(line)
        key = d["scene"]["rtol"]
        err = abs(d["peak_rotation_ratio"] - ref) / ref
        us = d["wall_seconds"] * 1e6
        prev = rock.get(key)
        # The method auto chose: DOP853 takes 12 RHS calls per trial step (15 with its dense
        # output), Dormand–Prince 5(4) 6.
        method = "dop853" if d["rhs_evals"] > 10 * (d["steps"] + d["rejected_steps"]) else "dp54"
        rock[key] = (err, d["rhs_evals"], min(us, prev[2]) if prev else us, method)
    ratios = []
    for target in (1e-4, 1e-6, 1e-8):
        def pick(table):
            ok = [r for r, v in table.items() if v[0] <= target]
            return (max(ok), table[max(ok)]) if ok else None
        p, r = pick(peer), pick(rock)
        if p is None or r is None:
            print(f"| {scene} | {target:.0e} | {'—' if p is None else p[0]} | | | | {'—' if r is None else r[0]} | | | | | |")
            continue
        ratio = p[1][2] / r[1][2]
        ratios.append(ratio)
        print(f"| {scene} | {target:.0e} | {p[0]:.0e} | {p[1][1]} | {p[1][2]:.1f} | {p[1][2] / p[1][1] * 1e3:.1f} "
              f"| {r[0]:.0e} | {r[1][3]} | {r[1][1]} | {r[1][2]:.1f} | {r[1][2] / r[1][1] * 1e3:.1f} | {ratio:.2f} |")
    if ratios:
        geo = math.exp(sum(map(math.log, ratios)) / len(ratios))
        notes.append(f"{scene}: geometric mean of peer/rocklab time over the targets met: {geo:.2f}")
    notes.append(open(f"{work}/rhs.{scene}").read().strip())
print()
for n in notes:
    print(f"- {n}")
EOF
