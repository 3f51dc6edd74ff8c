"""Element-integrated subsurface stress influence coefficients (paper Eq. 16: T^N, T^Sx, T^Sy).

The stress at depth ``z`` (mm, z > 0 into the half-space) caused by a *uniform unit* traction
over one rectangular surface element of size ``dx × dy`` (mm) centred at the origin, evaluated
at horizontal offsets ``(x, y)`` of the field point from the element centre. The coefficients
are dimensionless (MPa of stress per MPa of traction) and depend on the Poisson ratio of the
loaded body only.

Loads (the package convention, body A is the half-space):
- ``"pressure"``: p_n >= 0, compressive, pushing into the half-space (Boussinesq; Love 1929);
  at the surface under the element σzz → −1.
- ``"traction_x"`` / ``"traction_y"``: shear traction acting *on* the half-space surface in
  +x / +y (Cerruti); at the surface under the element σxz → −1 (σyz → −1).
Stress sign: tension positive, compression negative. Component keys: ``'xx', 'yy', 'zz',
'xy', 'xz', 'yz'``.

Method. With ρ = √(X² + Y² + z²), X = x − ξ, Y = y − η (field minus source point), the point
solutions follow from the potentials of Love (1929) / Johnson, *Contact Mechanics* (1985)
§3.2: Ω = z ln(ρ + z) − ρ, ∂Ω/∂z = ln(ρ + z), ∂²Ω/∂z² = 1/ρ. For a unit normal load
(Johnson Eq. 3.10–3.11, ψ₁ = ln(ρ+z), ψ = 1/ρ)

    σxx = [2ν ψ_z − z ψ_xx − (1 − 2ν) ψ₁_xx] / 2π,   σzz = [ψ_z − z ψ_zz] / 2π,
    σxy = −[(1 − 2ν) ψ₁_xy + z ψ_xy] / 2π,          σxz = −z ψ_xz / 2π,

and for a unit tangential load in +x (derived from Johnson Eq. 3.7 with F₁ = Ω, ψ₁ = Ω_x)

    σxx = [2(1 + ν) ψ_x + 2ν Ω_xxx − z ψ₁_zxxx] / 2π,  σyy = [2ν ψ_x + 2ν Ω_xyy − z Ω_zxyy] / 2π,
    σzz = −z ψ_xz / 2π,  σxy = [ψ_y + 2ν Ω_xxy − z Ω_zxxy] / 2π,
    σxz = [ψ_z − z ψ_xx] / 2π,  σyz = −z ψ_xy / 2π.

Integrating over the element moves one x- and one y-integration onto "corner functions" C
with ∂²C/∂X∂Y = point kernel; the element value is the double difference over the corners

    [C] = C(x + a, y + b) − C(x + a, y − b) − C(x − a, y + b) + C(x − a, y − b),

a = dx/2, b = dy/2 (as for the surface coefficients in NOTES.md). Terms of C that depend on X
only or on Y only cancel in [C] and are dropped; the remaining closed forms (logarithms and
arctangents, as in Love 1929 for the pressure and Liu & Wang 2002, J. Tribol. 124:36–45, for
the shear) are written in forms that stay finite and free of cancellation for every X, Y
(including X = 0, Y = 0, and the edge-over-corner case X = Y = 0) as long as z > 0:
ln(Y + ρ) is replaced by asinh(Y/√(X² + z²)), and atan(Y/X) − atan(zY/(Xρ)) by one arctan2.
The tests compare every coefficient with quadrature of the point-load solutions.
"""

from __future__ import annotations

import numpy as np

COMPONENTS = ("xx", "yy", "zz", "xy", "xz", "yz")
LOADS = ("pressure", "traction_x", "traction_y")

# Stress components of the traction_y corner functions, taken from traction_x with x <-> y.
_SWAP_XY = {"xx": "yy", "yy": "xx", "zz": "zz", "xy": "xy", "xz": "yz", "yz": "xz"}


def _in_plane_arctan(X: np.ndarray, Y: np.ndarray, z: float, rho: np.ndarray) -> np.ndarray:
    """atan(Y/X) − atan(zY/(Xρ)), continuous through X = 0 (value 0 there) and X = Y = 0."""
    return np.arctan2(X * Y * (X * X + Y * Y), (rho + z) * (X * X * rho + z * Y * Y))


def pressure_corner(X: np.ndarray, Y: np.ndarray, z: float, poisson_ratio: float) -> dict:
    """Corner functions (times 2π) of a uniform unit pressure; see the module docstring."""
    nu = poisson_ratio
    X2, Y2, z2 = X * X, Y * Y, z * z
    rho = np.sqrt(X2 + Y2 + z2)
    solid = np.arctan(X * Y / (z * rho))
    return {
        "xx": -2.0 * nu * solid
        + z * X * Y / (rho * (X2 + z2))
        - (1.0 - 2.0 * nu) * _in_plane_arctan(X, Y, z, rho),
        "yy": -2.0 * nu * solid
        + z * X * Y / (rho * (Y2 + z2))
        - (1.0 - 2.0 * nu) * _in_plane_arctan(Y, X, z, rho),
        "zz": -solid - z * X * Y * (rho * rho + z2) / (rho * (X2 + z2) * (Y2 + z2)),
        "xy": -(1.0 - 2.0 * nu) * np.log(rho + z) - z / rho,
        "xz": z2 * Y / (rho * (X2 + z2)),
        "yz": z2 * X / (rho * (Y2 + z2)),
    }


def traction_x_corner(X: np.ndarray, Y: np.ndarray, z: float, poisson_ratio: float) -> dict:
    """Corner functions (times 2π) of a uniform unit shear traction in +x (Cerruti)."""
    nu = poisson_ratio
    X2, Y2, z2 = X * X, Y * Y, z * z
    rho = np.sqrt(X2 + Y2 + z2)
    log_y = np.arcsinh(Y / np.sqrt(X2 + z2))  # ln(Y + ρ) up to a function of X alone
    log_x = np.arcsinh(X / np.sqrt(Y2 + z2))
    return {
        "xx": 2.0 * log_y
        + 2.0 * nu * X2 * Y / (rho * (X2 + z2))
        - (1.0 - 2.0 * nu) * z * Y * (z * rho - X2) / (rho * (rho + z) * (X2 + z2)),
        "yy": 2.0 * nu * log_y - 2.0 * nu * Y / (rho + z) - z * Y / (rho * (rho + z)),
        "zz": z2 * Y / (rho * (X2 + z2)),
        "xy": log_x - 2.0 * nu * X / (rho + z) - z * X / (rho * (rho + z)),
        "xz": -np.arctan(X * Y / (z * rho)) + z * X * Y / (rho * (X2 + z2)),
        "yz": -z / rho,
    }


def traction_y_corner(X: np.ndarray, Y: np.ndarray, z: float, poisson_ratio: float) -> dict:
    """Corner functions (times 2π) of a uniform unit shear traction in +y: x ↔ y of traction_x."""
    swapped = traction_x_corner(Y, X, z, poisson_ratio)
    return {component: swapped[_SWAP_XY[component]] for component in COMPONENTS}


_CORNERS = {
    "pressure": pressure_corner,
    "traction_x": traction_x_corner,
    "traction_y": traction_y_corner,
}


# Parity (+1 even, −1 odd) in X and in Y of each corner function above; every one of them
# has a definite parity, so on a lattice of corners symmetric about 0 only the quadrant
# X >= 0, Y >= 0 is evaluated and the rest mirrored (four times fewer evaluations).
_PARITY = {
    "pressure": {
        "xx": (-1, -1),
        "yy": (-1, -1),
        "zz": (-1, -1),
        "xy": (1, 1),
        "xz": (1, -1),
        "yz": (-1, 1),
    },
    "traction_x": {
        "xx": (1, -1),
        "yy": (1, -1),
        "zz": (1, -1),
        "xy": (-1, 1),
        "xz": (-1, -1),
        "yz": (1, 1),
    },
}
_PARITY["traction_y"] = {c: _PARITY["traction_x"][_SWAP_XY[c]][::-1] for c in COMPONENTS}


def kernel_parity(load: str, component: str) -> tuple[int, int]:
    """Parity (+1 even, −1 odd) in x and in y of the element coefficient of ``component``.

    Each integration in x and y flips the parity of the corner function.
    """
    parity_x, parity_y = _PARITY[load][component]
    return -parity_x, -parity_y


def _is_lattice(offsets: np.ndarray, spacing: float) -> bool:
    """True if ``offsets`` step by exactly one element size, so corners can be shared."""
    if offsets.size < 2:
        return False
    steps = np.diff(offsets)
    return bool(np.allclose(steps, spacing, rtol=1e-12, atol=1e-12 * spacing))


def _corner_coordinates(offsets: np.ndarray, spacing: float) -> tuple[np.ndarray, bool]:
    if _is_lattice(offsets, spacing):
        corners = offsets[0] - 0.5 * spacing + spacing * np.arange(offsets.size + 1)
        return corners, True
    return np.concatenate([offsets - 0.5 * spacing, offsets + 0.5 * spacing]), False


def _half(corners: np.ndarray, spacing: float) -> np.ndarray | None:
    """The non-negative half of a corner lattice symmetric about 0 (ascending), else None."""
    if corners.size < 2 or not np.allclose(corners, -corners[::-1], rtol=0, atol=1e-9 * spacing):
        return None
    half = corners[corners.size // 2 :].copy()
    if corners.size % 2:
        half[0] = 0.0
    return half


def _mirror(values: np.ndarray, parity: int, size: int, axis: int) -> np.ndarray:
    """Extend values on the non-negative half of a symmetric lattice of ``size`` to all of it."""
    reflected = parity * np.flip(values, axis=axis)
    if size % 2:  # the corner at 0 (last after the flip) is not repeated
        reflected = reflected[:-1] if axis == 0 else reflected[:, :-1]
    return np.concatenate([reflected, values], axis=axis)


def _corner_values(load, corner_x, corner_y, spacing, depth, poisson_ratio, components):
    """Corner functions on the tensor lattice corner_x × corner_y, using their parity."""
    function = _CORNERS[load]
    half_x, half_y = _half(corner_x, spacing[0]), _half(corner_y, spacing[1])
    X, Y = np.meshgrid(
        corner_x if half_x is None else half_x,
        corner_y if half_y is None else half_y,
        indexing="ij",
    )
    values = function(X, Y, depth, poisson_ratio)
    del X, Y
    result = {}
    for component in components:
        value = values.pop(component)  # each quadrant freed once mirrored
        parity_x, parity_y = _PARITY[load][component]
        if half_x is not None:
            value = _mirror(value, parity_x, corner_x.size, axis=0)
        if half_y is not None:
            value = _mirror(value, parity_y, corner_y.size, axis=1)
        result[component] = value
    return result


def _difference(values: np.ndarray, shared: bool, axis: int) -> np.ndarray:
    """Upper minus lower corner along ``axis``."""
    if shared:
        return np.diff(values, axis=axis)
    lower, upper = np.split(values, 2, axis=axis)
    return upper - lower


def element_stress(
    x: np.ndarray,
    y: np.ndarray,
    depth: float,
    dx: float,
    dy: float,
    poisson_ratio: float,
    load: str,
    components: tuple[str, ...] = COMPONENTS,
) -> dict[str, np.ndarray]:
    """Stress per unit uniform traction on one ``dx × dy`` element, on the grid ``x × y``.

    Parameters
    ----------
    x, y : 1-D arrays of field-point offsets from the element centre (mm), lengths m_x, m_y.
    depth : z > 0 (mm). z = 0 is excluded: the surface limit is discontinuous at the element
        edges; evaluate a small positive depth instead.
    dx, dy : element size (mm).
    poisson_ratio : ν of the loaded half-space.
    load : ``"pressure"``, ``"traction_x"`` or ``"traction_y"`` (conventions in module doc).
    components : subset of ``COMPONENTS`` to return.

    Returns
    -------
    dict component -> array of shape ``(m_x, m_y)``, dimensionless (MPa per MPa).
    When ``x`` (``y``) steps by exactly ``dx`` (``dy``), as on the DC-FFT lattice, neighbouring
    field points share corners and the corner functions are evaluated once per corner; if
    those corners are also symmetric about 0, only on the quadrant X, Y >= 0 (by parity).
    """
    if load not in _CORNERS:
        raise ValueError(f"load must be one of {LOADS}, got {load!r}")
    if not depth > 0.0:
        raise ValueError(f"depth must be > 0 mm, got {depth!r}")
    x = np.asarray(x, dtype=float).ravel()
    y = np.asarray(y, dtype=float).ravel()
    corner_x, shared_x = _corner_coordinates(x, dx)
    corner_y, shared_y = _corner_coordinates(y, dy)
    if shared_x and shared_y:
        corner = _corner_values(
            load, corner_x, corner_y, (dx, dy), float(depth), poisson_ratio, components
        )
    else:
        X, Y = np.meshgrid(corner_x, corner_y, indexing="ij")
        corner = _CORNERS[load](X, Y, float(depth), poisson_ratio)
    scale = 1.0 / (2.0 * np.pi)
    result = {}
    for component in components:
        values = _difference(corner.pop(component), shared_x, axis=0)  # corners freed as used
        result[component] = scale * _difference(values, shared_y, axis=1)
    return result


# --- Point-load solution (reference for tests and users) --------------------------------------


def cerruti_point_stress(x, y, z, poisson_ratio: float) -> dict[str, np.ndarray]:
    """Stress (MPa per N) of a unit tangential point force in +x on the surface at the origin.

    Cerruti's solution as given by Johnson (1985) §3.3, with ρ = √(x² + y² + z²), z > 0 (mm):

        σxx = −x/(2πρ³) [3x²/ρ² − (1−2ν)/(ρ+z)² (ρ² − y² − 2ρy²/(ρ+z))]
        σyy = −x/(2πρ³) [3y²/ρ² − (1−2ν)/(ρ+z)² (3ρ² − x² − 2ρx²/(ρ+z))]
        σxy = −y/(2πρ³) [3x²/ρ² + (1−2ν)/(ρ+z)² (ρ² − x² − 2ρx²/(ρ+z))]
        σzz = −3xz²/(2πρ⁵),  σxz = −3x²z/(2πρ⁵),  σyz = −3xyz/(2πρ⁵).

    The tests check it against the Cerruti displacement field differentiated numerically.
    The force in +y follows with x ↔ y.
    """
    nu = poisson_ratio
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    rho = np.sqrt(x * x + y * y + z * z)
    rho2 = rho * rho
    c = 1.0 / (2.0 * np.pi * rho**3)
    b = (1.0 - 2.0 * nu) / (rho + z) ** 2
    return {
        "xx": -c * x * (3.0 * x * x / rho2 - b * (rho2 - y * y - 2.0 * rho * y * y / (rho + z))),
        "yy": -c
        * x
        * (3.0 * y * y / rho2 - b * (3.0 * rho2 - x * x - 2.0 * rho * x * x / (rho + z))),
        "zz": -3.0 * c * x * z * z / rho2,
        "xy": -c * y * (3.0 * x * x / rho2 + b * (rho2 - x * x - 2.0 * rho * x * x / (rho + z))),
        "xz": -3.0 * c * x * x * z / rho2,
        "yz": -3.0 * c * x * y * z / rho2,
    }
