"""Save worn states of the regime study (peak-load pressure and tractions) as a test fixture.

The states of ``studies/peak_regime_32.toml`` for μ = 0.1 at N = 10⁵ that the region test
(tests/test_peak_regions.py) classifies: i = 1.33e-6 1/MPa (ω_max/δ0 ≈ 0.5, just past the
transition, where the plane's surface layer on the axis is inflated by the traction jump)
and i = 1.33e-5 1/MPa (ω_max/δ0 ≈ 2.7, the long-wear limit: the unworn centre carries the
load). Each is one case of that study run alone (same settings, ``record = [100000]``).

Run:  python scripts/peak_regime_states.py WORN.h5 HEAVY.h5 tests/data/peak_regime_32_worn.npz
Time: the two runs, 3–6 min each on one core (the extraction itself < 1 s).
"""

from __future__ import annotations

import argparse
import json

import h5py
import numpy as np


def peak_load_state(path: str, cycle: int = 100000) -> dict[str, np.ndarray]:
    """The recorded peak-load pressure and tractions (MPa) of the single case of ``path``,
    with its wear coefficient, maximum wear depth (mm) and unworn approach δ0 (mm)."""
    with h5py.File(path, "r") as file:
        (case,) = file["cases"].values()
        fields = case["fields"][f"cycle_{cycle:07d}"]
        summary = json.loads(case.attrs["summary"])
        return {
            "pressure": np.asarray(fields["pressure"]),
            "traction_x": np.asarray(fields["traction_x"]),
            "traction_y": np.asarray(fields["traction_y"]),
            "wear": np.asarray(float(case.attrs["wear1"])),
            "max_wear_depth": np.asarray(summary["max_wear_depth"]),
            "elastic_approach": np.asarray(summary["elastic_approach"]),
        }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("worn", help="results of μ = 0.1, i = 1.33e-6 (32², 10⁵ cycles)")
    parser.add_argument("heavy", help="results of μ = 0.1, i = 1.33e-5 (32², 10⁵ cycles)")
    parser.add_argument("out", help="the .npz to write")
    args = parser.parse_args()
    arrays = {}
    for name, path in (("worn", args.worn), ("heavy", args.heavy)):
        arrays |= {f"{name}_{key}": value for key, value in peak_load_state(path).items()}
    np.savez_compressed(args.out, **arrays)
    print(f"{args.out}: {', '.join(sorted(arrays))}")


if __name__ == "__main__":
    main()
