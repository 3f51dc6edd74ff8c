"""Example plug-ins for fretting-engine, registered through entry points (see
``pyproject.toml``): a conical punch (:class:`~.cone.ConePunch`, ``[punch] shape = "cone"``
with its own key ``angle``), a fatigue criterion (:class:`~.shear.ShearAmplitude`,
``[fatigue] criteria = ["shear_amplitude"]`` with its constant ``tau_a``) and a wear law
(:class:`~.threshold.ThresholdWear`, ``[wear] law = "threshold"`` with its coefficients
``wear_rate`` and ``threshold_pressure``)."""

from .cone import ConePunch
from .shear import ShearAmplitude
from .threshold import ThresholdWear

__all__ = ["ConePunch", "ShearAmplitude", "ThresholdWear"]
