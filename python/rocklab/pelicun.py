"""``rocklab.to_pelicun``: a variant's peaks as a pelicun demand sample.

pelicun (``DemandModel.load_sample``) reads a CSV whose columns are demands named
``EVENT-TYPE-LOCATION-DIRECTION``, whose first row (``Units``) gives each column's unit,
and whose rows are realisations. Here each scene of one variant is a realisation.
"""

import os
from pathlib import Path
from typing import Optional, Union

from . import _native

#: pelicun's demand type for each rocklab quantity that has one (a quantity not listed has
#: no pelicun counterpart and is left out): drift is pelicun's interstory drift, the
#: absolute acceleration its floor acceleration; a rocking rotation is a demand of its own.
DEMAND_TYPES = {
    "peak_drift": "PID",
    "peak_abs_acceleration": "PFA",
    "peak_rotation": "ROT",
    "peak_rotation_ratio": "RROT",
    "peak_deformation": "DEF",
}

#: rocklab's units (the quantity table's) in pelicun's spelling.
UNITS = {"rad": "rad", "g": "g", "m": "m", "": "unitless"}


def to_pelicun(results, path: Union[str, "os.PathLike[str]"],
               group: Optional[str] = None, excitation: Optional[str] = None) -> Path:
    """Write the peaks of one variant (``group``, a value of the results' ``group``
    column; optional when there is one) as a pelicun demand sample CSV at ``path``, one
    realisation per scene, optionally of one ``excitation``. Failed scenes are written
    with pelicun's ``ERROR`` column set, so that pelicun drops them. Returns the path.
    """
    import pandas as pd

    wide = results.table(wide=True)
    groups = list(dict.fromkeys(wide["group"]))
    if group is None:
        if len(groups) != 1:
            raise ValueError(f"the results hold {len(groups)} variants; pass group= one of "
                             f"{groups}")
        group = groups[0]
    rows = wide[wide["group"] == group]
    if excitation is not None:
        rows = rows[rows["excitation"] == excitation]
    if rows.empty:
        raise ValueError(f"no scene of group {group!r}"
                         + (f" under {excitation!r}" if excitation else "")
                         + f"; groups: {groups}")
    units = dict(_native.quantity_units())
    columns = {}
    unit_row = {}
    for quantity, demand in DEMAND_TYPES.items():
        if quantity in rows.columns and rows[quantity].notna().any():
            name = f"1-{demand}-1-1"
            columns[name] = rows[quantity].to_numpy()
            unit_row[name] = UNITS[units[quantity]]
    columns["1-ERROR-1-1"] = (rows["status"] != "ok").to_numpy().astype(int)
    unit_row["1-ERROR-1-1"] = "unitless"
    sample = pd.DataFrame(columns)
    out = pd.concat([pd.DataFrame([unit_row], index=["Units"]), sample])
    path = Path(path)
    out.to_csv(path)
    return path
