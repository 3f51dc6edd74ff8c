"""Check a fretting map's results against Mindlin (studies/fretting_map.toml, docs/fretting.md).

    python scripts/check_fretting_map.py results/fretting_map.h5

For every case of a displacement-controlled sphere study with isotropic friction and the
energy wear law, prints what does not hold and the worst figures: the slip regime against
the side of Mindlin's δ_slip(P) the amplitude lies on; the first simulated cycle's energy
against the exact Mindlin energy and (gross slip) against the analytic loop sampled at the
solver's own increments (the load-step error removed); the wear volume over α times the
cumulated dissipated energy (1 for the energy law); the largest contact radius over Hertz's a
(it must stay below the mesh half-width, 1.5 a by default). Exit code 1 if a regime is wrong.
"""

from __future__ import annotations

import sys

import numpy as np

from engine.analysis.fretting_figures import _regime, cumulated_energy, read_loops
from engine.analysis.reader import read_results
from engine.reference import mindlin
from engine.reference.hertz import hertz_contact_radius


def sampled_loop_energy(delta, amplitude, reference_args) -> float:
    """∮ Q dδ (mJ) of the analytic loop sampled at the solver's displacements ``delta`` (mm),
    unloading on the first half of the rows, reloading on the second (trapezoidal rule)."""
    limit = reference_args[-1] * reference_args[0]
    peak = float(mindlin.force_amplitude(amplitude, *reference_args))

    def unloading(x):
        return np.maximum(
            peak - 2 * mindlin.tangential_force((amplitude - x) / 2, *reference_args), -limit
        )

    half = len(delta) // 2
    force = np.concatenate([unloading(delta[: half + 1]), -unloading(-delta[half + 1 :])])
    return float(np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(delta)))


def main(path: str) -> int:
    study = read_results(path)
    material, radius = study.material, float(study.config["punch"]["radius"])
    wrong, ratios, worst, sampled, widest = [], [], {"partial": 0.0, "gross": 0.0}, 0.0, 0.0
    for case in study.cases:
        load, amplitude = case.settings["loading.load"], case.settings["loading.amplitude"]
        args = (load, radius, material, case.mu1)
        expected = "gross" if amplitude > mindlin.slip_displacement(*args) else "partial"
        if _regime(case) != expected:
            wrong.append(f"{case.case_id}: {_regime(case)}, Mindlin says {expected}")
        energy = float(case.history["energy"][1])
        exact = float(mindlin.energy_per_cycle(amplitude, *args))
        worst[expected] = max(worst[expected], abs(energy / exact - 1))
        if expected == "gross":
            delta = read_loops(path, case.case_id)[1][:, 0]
            sampled = max(sampled, abs(energy / sampled_loop_energy(delta, amplitude, args) - 1))
        alpha = case.summary.get("alpha")
        if alpha:
            cumulated = cumulated_energy(case)[1:]
            ratios.append(case.history["wear_volume"][1:] / (alpha * cumulated))
        a = hertz_contact_radius(load, radius, material.contact_modulus)
        widest = max(widest, case.summary["contact_radius"] / a)
    print("\n".join(wrong) or f"slip regimes: all {len(study.cases)} on Mindlin's side")
    print(f"energy vs Mindlin: partial {worst['partial']:.2%}, gross {worst['gross']:.2%}; "
          f"gross vs the sampled analytic loop {sampled:.2%}")  # fmt: skip
    if ratios:
        ratio = np.concatenate(ratios)
        print(f"wear volume / (α E_d): {ratio.min():.5f} … {ratio.max():.5f}")
    print(f"largest contact radius: {widest:.3f} a")
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
