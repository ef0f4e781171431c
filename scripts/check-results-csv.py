#!/usr/bin/env python3
"""Check that pandas reads a results.csv with no option and no renaming.

Usage: scripts/check-results-csv.py out/fig12   (a run's output directory)
"""
import re
import sys

import pandas as pd

out = sys.argv[1] if len(sys.argv) > 1 else "out/fig12"
table = pd.read_csv(f"{out}/results.csv")
columns = pd.read_csv(f"{out}/results.columns.csv")
identifier = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,62}$")
bad = [c for c in table.columns if not identifier.match(c)]
assert not bad, f"not plain identifiers: {bad}"
missing = set(table.columns) - set(columns["name"])
assert not missing, f"not described in results.columns.csv: {missing}"
assert len(table) > 0 and table["value"].notna().any()
print(f"{out}/results.csv: {len(table)} rows, columns {list(table.columns)}")
print(columns[["name", "label", "unit"]].to_string(index=False))
