"""``[wear] law = "threshold"``: Archard's isotropic law above a threshold pressure,

    Δω = k ⟨p − p_th⟩ |Δs|,

with Δω the wear depth of one increment (mm), k ``wear_rate`` (1/MPa), p the contact
pressure (MPa), p_th ``threshold_pressure`` (MPa), ⟨x⟩ = max(x, 0) and |Δs| the length of the
slip increment (mm). Below p_th the surface does not wear (a protective oxide or third-body
layer carrying the lighter loads); with p_th = 0 it is the engine's ``"archard"`` law with
i1 = i2 = k. A plain example of the protocol of ``engine.solvers.wear``: the two coefficients
are its own ``[sweep]`` lists, summary columns and case parameters.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from engine.keys import Key
from engine.solvers.wear import WearModel

__all__ = ["ThresholdWear"]


@dataclass(frozen=True)
class ThresholdWear(WearModel):
    """``wear_rate`` k (1/MPa) and ``threshold_pressure`` p_th (MPa), module docstring."""

    wear_rate: float
    threshold_pressure: float

    name = "threshold"
    description = "Archard above a threshold pressure: depth increment = k ⟨p − p_th⟩ |Δs|"
    id_prefix = "t"
    coefficients = {
        "wear_rate": Key(
            "1/MPa", "wear rate k above the threshold pressure", minimum=0.0, maximum=1e-3,
            why="Archard's bound: fretting tests wear at 1e-9 … 1e-6", example=1.33e-7,
        ),
        "threshold_pressure": Key(
            "MPa", "contact pressure p_th below which the surface does not wear",
            minimum=0.0, maximum=1e4, why="10 GPa: above the strength of any steel",
            example=100.0,
        ),
    }  # fmt: skip

    def __post_init__(self) -> None:
        for name, key in self.coefficients.items():
            object.__setattr__(self, name, key.check(name, getattr(self, name)))

    @classmethod
    def from_coefficients(cls, values, beta: float) -> ThresholdWear:
        return cls(values["wear_rate"], values["threshold_pressure"])

    def increment(self, result, previous) -> np.ndarray:
        """Δω = k ⟨p − p_th⟩ |Δs| (mm) from the increment's pressure (MPa) and slips (mm)."""
        excess = np.maximum(result.pressure - self.threshold_pressure, 0.0)
        return self.wear_rate * excess * np.hypot(result.slip_x, result.slip_y)

    def scaled(self, factor: float) -> ThresholdWear:
        """The rate times ``factor``, the same threshold (two bodies wearing together)."""
        return ThresholdWear(self.wear_rate * factor, self.threshold_pressure)
