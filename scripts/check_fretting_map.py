"""Check a fretting map's results against Mindlin (studies/fretting_map.toml).

See docs/how-to/fretting.md.

    python scripts/check_fretting_map.py results/fretting_map.h5

For every case of a sphere study with isotropic friction, prints what does not hold and the
worst figures (engine.analysis.fretting.check_case): the slip regime of the first simulated
cycle against the side of Mindlin's δ_slip(P) the amplitude lies on; the energy per cycle at
N = 1 against the exact Mindlin energy and (gross slip) against the analytic loop sampled at
the solver's own increments (the load-step error removed); the wear volume over α times the
cumulated dissipated energy (1 for the energy law); the largest contact radius over Hertz's a
(it must stay below the mesh half-width, 1.5 a by default). Exit code 1 if a regime is wrong.
``python -m engine report`` prints the same checks per case.
"""

from __future__ import annotations

import sys

import numpy as np

from engine.analysis.fretting import (
    case_profile,
    check_case,
    material,
    setting,
    wear_energy_ratios,
)
from engine.analysis.results import open_results


def main(path: str) -> int:
    study = open_results(path)
    wrong, ratios, worst, sampled, widest = [], [], {"partial": 0.0, "gross": 0.0}, 0.0, 0.0
    for case in study.completed:
        check = check_case(study, case)
        if check is not None:
            if not check.regime_holds:
                wrong.append(f"{case.case_id}: {check.computed}, Mindlin says {check.expected}")
            worst[check.expected] = max(worst[check.expected], abs(check.energy_error))
            if np.isfinite(check.sampled_error):
                sampled = max(sampled, abs(check.sampled_error))
        ratios.append(wear_energy_ratios(study, case))
        load = float(setting(study, case, "loading.load"))
        a = case_profile(study, case).contact_length(load, material(study, case).contact_modulus)
        widest = max(widest, case.summary["contact_radius"] / a)
    print("\n".join(wrong) or f"slip regimes: all {len(study.completed)} on Mindlin's side")
    print(f"energy vs Mindlin: partial {worst['partial']:.2%}, gross {worst['gross']:.2%}; "
          f"gross vs the sampled analytic loop {sampled:.2%}")  # fmt: skip
    ratio = np.concatenate(ratios) if ratios else np.zeros(0)
    if ratio.size:
        print(f"wear volume / (α E_d): {ratio.min():.5f} … {ratio.max():.5f}")
    print(f"largest contact radius: {widest:.3f} a")
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
