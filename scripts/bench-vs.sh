#!/usr/bin/env bash
# Equal-error comparison of two rocklab builds on the Fig. 8 bare and mechanistic scenes.
#
#   scripts/bench-vs.sh [OLD] [ROUNDS]
#
# OLD: a rocklab binary, or a git revision built here in a temporary worktree (its own
# target dir, release profile). Default: /work/bin/rocklab-c692c0f where it exists, else the
# revision c692c0f. The current build is target/release/rocklab (built first). Each round
# runs `rocklab bench --only <scene>` of OLD then NEW, scene by scene, so load on the machine
# hits both alike; times are medians over ROUNDS (default 3). For each target error (1e-4,
# 1e-6, 1e-8; the worst relative peak error against each build's own rtol 1e-12 reference)
# the table takes each build's loosest tolerance that meets it and prints RHS calls, time and
# the ratios old/new.
set -euo pipefail
cd "$(dirname "$0")/.."

OLD=${1:-}
ROUNDS=${2:-3}
RTOLS=${RTOLS:-1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11}
SCENES=("rigid bare, sine pulse" "rigid mechanistic, sine pulse")

if [[ -z "$OLD" ]]; then
    if [[ -x /work/bin/rocklab-c692c0f ]]; then OLD=/work/bin/rocklab-c692c0f; else OLD=c692c0f; fi
fi
WORK=$(mktemp -d)
cleanup() {
    if [[ -d "$WORK/src" ]]; then git worktree remove --force "$WORK/src" >/dev/null 2>&1 || true; fi
    rm -rf "$WORK"
}
trap cleanup EXIT

if [[ -x "$OLD" ]]; then
    OLD_BIN=$OLD
else
    echo "building $OLD in a temporary worktree ..." >&2
    git worktree add --detach "$WORK/src" "$OLD" >/dev/null
    cargo build --release --quiet --manifest-path "$WORK/src/Cargo.toml" \
        --target-dir "$WORK/target" --bin rocklab
    OLD_BIN=$WORK/target/release/rocklab
fi
cargo build --release --quiet --bin rocklab
NEW_BIN=target/release/rocklab
echo "old: $OLD ($OLD_BIN); new: $(git rev-parse --short HEAD)$(git diff --quiet || echo '+dirty') ($NEW_BIN)" >&2

for round in $(seq "$ROUNDS"); do
    for scene in "${SCENES[@]}"; do
        for which in old new; do
            bin=$OLD_BIN; [[ $which == new ]] && bin=$NEW_BIN
            "$bin" bench --only "$scene" --no-sweeps --repeats 1 --rtol "$RTOLS" \
                >"$WORK/$which.$round.${scene// /_}.md"
        done
    done
done

python3 - "$WORK" "$ROUNDS" "${SCENES[@]}" <<'EOF'
import statistics, sys
work, rounds, scenes = sys.argv[1], int(sys.argv[2]), sys.argv[3:]

def rows(path, scene):
    """rtol -> (worst error, RHS calls, time ms) from the scene's work-precision table."""
    out, inside = {}, False
    for line in open(path, encoding="utf-8"):
        if line.startswith("## "):
            inside = line[3:].strip() == scene
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if inside and len(cells) == 9 and cells[0][:1].isdigit():
            errors = [float(c) for c in cells[1:5]]
            out[float(cells[0])] = (max(errors), int(cells[7]), float(cells[8]))
    return out

print("| scene | target err | old rtol | old RHS | old ms | new rtol | new RHS | new ms | RHS old/new | time old/new |")
print("|---|---|---|---|---|---|---|---|---|---|")
for scene in scenes:
    best = {}
    for which in ("old", "new"):
        runs = [rows(f"{work}/{which}.{r}.{scene.replace(' ', '_')}.md", scene) for r in range(1, rounds + 1)]
        merged = {}
        for rtol in runs[0]:
            err, rhs, _ = runs[0][rtol]
            merged[rtol] = (err, rhs, statistics.median(run[rtol][2] for run in runs))
        best[which] = merged
    for target in (1e-4, 1e-6, 1e-8):
        pick = {}
        for which, table in best.items():
            ok = [rtol for rtol, (err, _, _) in table.items() if err <= target]
            pick[which] = (max(ok), *table[max(ok)][1:]) if ok else None
        o, n = pick["old"], pick["new"]
        if o is None or n is None:
            print(f"| {scene} | {target:.0e} | {'—' if o is None else o[0]} | | | {'—' if n is None else n[0]} | | | | |")
            continue
        print(f"| {scene} | {target:.0e} | {o[0]:.0e} | {o[1]} | {o[2]:.3f} | {n[0]:.0e} | {n[1]} | {n[2]:.3f} "
              f"| {o[1] / n[1]:.2f} | {o[2] / n[2]:.2f} |")
EOF
