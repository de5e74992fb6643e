#!/usr/bin/env python3
"""Reference heights of every OpenCRG file in data/chrono from an independent reader, PyOpenCRG
(pip install pyopencrg==0.2.2: pure Python on numpy, written from the OpenCRG reference implementation,
not from the `opencrg` crate the model uses). tests/roads.rs compares the model's heights against them.

Usage: .venv/bin/python scripts/crg_reference.py [CHRONO_DATA_DIR] > tests/reference/crg/heights.csv
Points: 40 per file, seeded (numpy default_rng(8608)), uniform inside the grid's u and v ranges shrunk by
1 % at each edge (the border modes are not what is compared).
"""
import pathlib
import sys

import numpy as np
import pyopencrg


def main(argv):
    data = pathlib.Path(argv[1] if len(argv) > 1 else "data/chrono")
    files = sorted((data / "terrain" / "crg_roads").glob("*.crg"))
    rng = np.random.default_rng(8608)
    print("file,u_m,v_m,z_m")
    for f in files:
        # The modifiers ($ROAD_CRG_MODS: NaN handling, offsets, scaling) applied, as the C-API and the
        # model apply them.
        road = pyopencrg.CrgRoad.read(str(f), apply_mods=True)
        u0, u1 = float(road.u_start), float(road.u_end)
        v = np.asarray(road.v, dtype=float)
        v0, v1 = float(v.min()), float(v.max())
        du, dv = 0.01 * (u1 - u0), 0.01 * (v1 - v0)
        us = rng.uniform(u0 + du, u1 - du, 40)
        vs = rng.uniform(v0 + dv, v1 - dv, 40)
        zs = np.asarray(road.uv_to_z(us, vs), dtype=float)
        for u, vv, z in zip(us, vs, zs):
            print(f"{f.name},{float(u)!r},{float(vv)!r},{float(z)!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
