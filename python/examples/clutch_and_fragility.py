# %% [markdown]
# # rocklab in a notebook: a clutch-stiffness sweep and a fragility study
#
# Run as a script (`python examples/clutch_and_fragility.py [OUT_DIR]`) or cell by cell in
# Jupyter / VS Code (`# %%` cells). Figures go to OUT_DIR (default `out/examples`).
# The studies are small versions of `studies/fig18_clutch_stiffness.ron` and
# `studies/fragility_far_field.ron`, so the whole example runs in about a minute.

# %%
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files, not windows: also runs headless
import matplotlib.pyplot as plt

import rocklab

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out/examples")
out.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## A clutch-stiffness grid
# A rigid block under a one-sine pulse, the sequential law against the mechanistic clutch
# at four clutch frequencies √(kθ/J) = {12.5, 25, 50, 100} p.

# %%
clutch = rocklab.Study.from_ron("""(
    version: 1,
    name: "example_clutch_grid",
    structure: rigid(p: 2.0, alpha: 0.2),
    devices: [
        sequential(sigma: 0.5),
        mechanistic(sigma: 0.5, clutch_frequency_ratio: [12.5, 25.0, 50.0, 100.0], cbar: 1.0),
    ],
    excitation: pulse(
        shape: sine,
        amplitude: tan_alpha_ratio(1.5),
        frequency: ratio((from: 2.0, to: 12.0, steps: 11)),
    ),
    quantities: [peak_rotation_ratio],
    duration: 15.0,
)""")
grid = rocklab.run(clutch, out=out / "clutch_grid")
ds = grid.to_xarray()
ds

# %%
# One dimension per study axis: the variant (group), ωg/p and the clutch's ωc/p (NaN where
# a variant has no such member). One line per (variant, ωc/p) that ran:
da = ds["peak_rotation_ratio"]
x = "omega_g_over_p"
lines = da.stack(line=[d for d in da.dims if d != x]).dropna("line", how="all")
fig, ax = plt.subplots(figsize=(6, 4))
for i in range(lines.sizes["line"]):
    line = lines.isel(line=i)
    ax.plot(line[x], line, marker=".", label=str(line["group"].item()))
ax.set_xlabel("ωg/p")
ax.set_ylabel("θmax/α")
ax.set_title("Clutch stiffness: sequential vs mechanistic")
ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(out / "clutch_grid.png", dpi=120)

# %% [markdown]
# ## A fragility study
# Two far-field records (both components) at three intensities, bare against the sequential
# clutched inerter; lognormal fits by maximum likelihood over the stripes.

# %%
fragility = rocklab.run("""(
    version: 1,
    name: "example_fragility",
    structure: rigid(p: 2.0, alpha: 0.2),
    devices: [none, sequential(sigma: 0.5)],
    excitation: record(
        suite: (name: "far_field", records: [1, 2, 3]),
        scale: [1.5, 3.0, 6.0],
        scale_to: pga_star,
        tail: 2.0,
    ),
    quantities: [peak_rotation_ratio],
    spectrum: scale,
    fragility: (damage_states: levels([0.2, 1.0])),
)""", out=out / "fragility")
curves = fragility.fragility()
stripes = fragility.stripes()
curves

# %%
import math

import numpy as np

# A lognormal fragility: P(DS ≥ ds | IM) = Φ(ln(IM/median)/β), Φ(z) = (1 + erf(z/√2))/2.
phi = np.vectorize(lambda z: 0.5 * (1.0 + math.erf(z / math.sqrt(2.0))))
fig, ax = plt.subplots(figsize=(6, 4))
im = np.linspace(0.5, 10.0, 200)
fitted = curves.dropna(subset=["median", "beta"])
for _, row in fitted.iterrows():
    ax.plot(im, phi(np.log(im / row["median"]) / row["beta"]),
            label=f"{row['device']}, θmax/α ≥ {row['damage_state']}")
ax.set_xlabel("PGA/(g tanα)")
ax.set_ylabel("probability of exceedance")
ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(out / "fragility.png", dpi=120)
print(f"{len(fitted)} fitted curves; figures in {out}")
