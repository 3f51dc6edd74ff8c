"""Example plug-ins for fretting-engine, registered through entry points (see
``pyproject.toml``): a conical punch (:class:`~.cone.ConePunch`, ``[punch] shape = "cone"``
with its own key ``angle``) and a fatigue criterion (:class:`~.shear.ShearAmplitude`,
``[fatigue] criteria = ["shear_amplitude"]`` with its constant ``tau_a``)."""

from .cone import ConePunch
from .shear import ShearAmplitude

__all__ = ["ConePunch", "ShearAmplitude"]
