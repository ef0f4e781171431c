#!/usr/bin/env python3
"""How far a build moves the shipped studies' results: the largest change of every study.

    scripts/study-changes.py OLD_BINARY NEW_BINARY [WORKDIR]

Runs every studies/*.ron with both binaries (`run --fresh --quiet`), then per study: the largest
relative change of any value of results.csv, the overturn flags that flip, and the same for
design.csv, fragility.csv and stripes.csv where the study writes them. Scenes are matched by
their key (adaptive studies — IDA, design searches, adaptive maps — choose later scenes from
earlier results), or by index where most keys differ (a record whose data is unavailable keys
on that). A value that appears or vanishes (the overturn flag flips) counts as a flip, not in
the largest change. Every scene that moved by more than 1e-5 is then checked with the new binary
(`rocklab check --scenes`), and the table says how many of them are ill-conditioned, not
converged at their rtol, or converged, and lists any that is not ill-conditioned and moved more
than its own error against the 1000x tighter reference.
"""
import collections
import csv
import math
import os
import subprocess
import sys
import tempfile

MOVED = 1e-5


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def num(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def rel(a, b):
    return 0.0 if a == b else abs(b - a) / max(abs(a), 1e-300)


def run_all(binary, out):
    for name in sorted(os.listdir("studies")):
        if name.endswith(".ron"):
            dest = os.path.join(out, name[:-4])
            subprocess.run([binary, "run", f"studies/{name}", "--out", dest, "--fresh", "--quiet"],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def fmt(change):
    """A change as text: a value that appears or vanishes (an overturn flips) is 'flip'."""
    return "flip" if change == math.inf else f"{change:.1e}"


def compare(old_dir, new_dir, new_binary, work):
    ro, rn = rows(f"{old_dir}/results.csv"), rows(f"{new_dir}/results.csv")
    ko, kn = {r["key"] for r in ro}, {r["key"] for r in rn}
    field = "key" if len(ko & kn) > 0.9 * len(ko) else "scene"
    new_by = {(r[field], r["quantity"]): r for r in rn}
    worst, where, flips, moved = 0.0, "", 0, {}
    for r in ro:
        m = new_by.get((r[field], r["quantity"]))
        if m is None:
            continue
        a, b = num(r["value"]), num(m["value"])
        change = 0.0
        if r["overturned"] != m["overturned"]:
            flips += 1
            change = math.inf
        elif (a is None) != (b is None):
            change = math.inf
        elif a is not None:
            change = rel(a, b)
        if math.isfinite(change) and change > worst:
            worst, where = change, f"{r['quantity']}, scene {m['scene']}"
        if change > MOVED:
            moved[m["scene"]] = max(moved.get(m["scene"], 0.0), change)
    others = []
    for extra in ("design.csv", "fragility.csv", "stripes.csv"):
        if not os.path.exists(f"{old_dir}/{extra}"):
            continue
        w, text = 0.0, False
        for ra, rb in zip(rows(f"{old_dir}/{extra}"), rows(f"{new_dir}/{extra}")):
            for k, x in ra.items():
                a, b = num(x), num(rb.get(k))
                if a is None or b is None:
                    text |= x != rb.get(k)
                else:
                    w = max(w, rel(a, b))
        note = f"{w:.1e}" + (", a text cell differs" if text else "")
        others.append(f"{extra} {note}" if w or text else f"{extra} identical")
    verdicts, beyond = collections.Counter(), []
    if moved:
        checked = f"{work}/check.csv"
        subprocess.run([new_binary, "check", new_dir, "--scenes", ",".join(sorted(moved, key=int)),
                        "--csv", checked, "--worst", "0"], check=True, stdout=subprocess.DEVNULL)
        error = collections.defaultdict(float)
        verdict = {}
        for r in rows(checked):
            verdict[r["scene"]] = r["verdict"]
            error[r["scene"]] = max(error[r["scene"]], num(r["change"]) or 0.0)
        for scene, v in verdict.items():
            verdicts[v] += 1
            if v != "ill_conditioned" and moved[scene] > error[scene]:
                beyond.append(f"{scene} ({v}, moved {fmt(moved[scene])}, error {error[scene]:.1e})")
    largest = "identical" if worst == 0 else f"{worst:.1e} ({where})"
    checked = ", ".join(f"{n} {v}" for v, n in sorted(verdicts.items())) or "—"
    return largest, flips, "; ".join(others), len(moved), checked, "; ".join(beyond) or "—"


def main():
    old_binary, new_binary = sys.argv[1], sys.argv[2]
    work = sys.argv[3] if len(sys.argv) > 3 else tempfile.mkdtemp()
    run_all(old_binary, f"{work}/old")
    run_all(new_binary, f"{work}/new")
    print("| study | largest relative change of a value | overturn flips | other outputs | scenes moved > 1e-5 | "
          "their check verdicts | moved more than their own error (not ill-conditioned) |")
    print("|---|---|---|---|---|---|---|")
    for study in sorted(os.listdir(f"{work}/old")):
        cells = compare(f"{work}/old/{study}", f"{work}/new/{study}", new_binary, work)
        print(f"| {study} | " + " | ".join(str(c) for c in cells) + " |")


if __name__ == "__main__":
    main()
