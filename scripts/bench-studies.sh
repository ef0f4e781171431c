#!/usr/bin/env bash
# Wall time and scenes per second of shipped studies with 1 and 2 threads (best of 3, --fresh).
# Usage: scripts/bench-studies.sh [study.ron …]   (default: every runnable study in studies/)
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin=target/release/rocklab
out=$(mktemp -d)
studies=("$@")
[ ${#studies[@]} -eq 0 ] && studies=(studies/*.ron)
printf '| study | scenes | jobs | wall time (best of 3) | scenes/s |\n|---|---|---|---|---|\n'
for s in "${studies[@]}"; do
  name=$(basename "$s" .ron)
  for jobs in 1 2; do
    best=""
    for _ in 1 2 3; do
      start=$(date +%s.%N)
      if ! "$bin" run "$s" --out "$out/$name" --jobs "$jobs" --fresh --quiet 2>"$out/err"; then
        echo "| $name | – | $jobs | not runnable: $(tail -1 "$out/err") | – |"
        continue 3
      fi
      end=$(date +%s.%N)
      t=$(echo "$end - $start" | bc -l)
      if [ -z "$best" ] || (( $(echo "$t < $best" | bc -l) )); then best=$t; fi
    done
    n=$(grep -o '^[0-9]* scenes' "$out/err" | grep -o '[0-9]*')
    printf '| %s | %s | %s | %.2f s | %.0f |\n' "$name" "$n" "$jobs" "$best" "$(echo "$n / $best" | bc -l)"
  done
done
rm -rf "$out"
