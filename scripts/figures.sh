#!/usr/bin/env bash
# One PNG per shipped study in docs/figures/, for a reviewer to look at:
#   scripts/figures.sh                    # runs the studies into out/ first (reuses finished scenes)
#   RESULTS=some/dir scripts/figures.sh   # plots existing results some/dir/<study>/results.json
# Each study's spectra (all quantities as panels) or, for studies with a map, its overturning
# maps, or for fragility studies its fragility curves (fragility.png); plus the paper's Fig. 8/9/15
# histories of the Fig. 12 mechanistic scene at ωg/p = 4.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin=target/release/rocklab
results=${RESULTS:-out}
dest=docs/figures
mkdir -p "$dest"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for file in studies/*.ron; do
    study=$(basename "$file" .ron)
    if [[ ! -f "$results/$study/results.json" ]]; then
        "$bin" run "$file" --out "$results/$study" --quiet
    fi
    "$bin" plot "$results/$study" --png "$tmp/$study" --dpi 150 >/dev/null
    if [[ -f "$tmp/$study/risk.png" ]]; then
        cp "$tmp/$study/risk.png" "$dest/$study.png"
    elif [[ -f "$tmp/$study/fragility.png" ]]; then
        cp "$tmp/$study/fragility.png" "$dest/$study.png"
    elif [[ -f "$tmp/$study/maps.png" ]]; then
        cp "$tmp/$study/maps.png" "$dest/$study.png"
    else
        cp "$tmp/$study/spectra.png" "$dest/$study.png"
    fi
    echo "$dest/$study.png"
done
# Figs. 8, 9 and 15: the histories of scene 243 (mechanistic, ωg/p = 4) of Fig. 12's study.
"$bin" plot "$results/fig12_rigid_spectra" --png "$tmp/scene" --dpi 150 --scene 243 \
    --select mechanistic >/dev/null
cp "$tmp/scene/scene-243.png" "$dest/fig12_scene243_histories.png"
echo "$dest/fig12_scene243_histories.png"
# The overturning maps compared cell by cell: where only the protected block survives.
"$bin" plot "$results/overturning_map_rigid" --png "$tmp/difference" --dpi 150 \
    --a bare --b mechanistic >/dev/null 2>&1
cp "$tmp/difference/maps-difference.png" "$dest/overturning_map_rigid_difference.png"
echo "$dest/overturning_map_rigid_difference.png"
# The README's figure: Fig. 12 at a journal's full width.
"$bin" plot "$results/fig12_rigid_spectra" --png "$tmp/readme" --size 160x80mm --dpi 150 >/dev/null
cp "$tmp/readme/spectra.png" "$dest/fig12_readme.png"
echo "$dest/fig12_readme.png"
