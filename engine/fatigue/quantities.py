"""Quantities the criteria share, vectorised over points, planes and instants.

Every function takes a ``StressHistory`` (stresses in MPa, shape (n_instants, n_points, 6)).

- **Hydrostatic stress** σ_H = tr σ / 3; σ_H,max its maximum over the cycle (MPa).
- **Deviatoric coordinates**: the deviator s = σ − σ_H I mapped to R⁶ as
  v = (s_xx, s_yy, s_zz, √2 s_yz, √2 s_xz, √2 s_xy)/√2, so that |v|² = J2 = ½ s:s and the
  distance of two instants is √J2 of their difference.
- **Shear stress amplitude √J2,a** (MPa), the radius of the deviatoric path:
  ``"chord"`` (default) half the longest chord max_{t1,t2} |v(t1) − v(t2)| / 2 (exact over the
  sampled instants; equals the radius of the minimum ball for paths symmetric about a centre,
  e.g. proportional loading); ``"ball"`` the radius of the minimum circumscribed ball
  (Dang Van 1989; Papadopoulos et al., Int. J. Fatigue 19 (1997) 219), computed by
  pairwise Frank–Wolfe iterations on the dual problem (Yildirim, SIAM J. Optim. 19 (2008)
  1368; pairwise steps: Lacoste-Julien & Jaggi, NeurIPS 2015) to a relative gap of 1e-10 in
  the squared radius.
- **Planes** (critical-plane criteria): planes containing the y axis (perpendicular to the
  x–z plane evaluated), their trace in the x–z plane at the angle φ from +x towards +z,
  φ = 0, Δφ, …, 180° − Δφ (default Δφ = 1°); normal n = (−sin φ, 0, cos φ); resolved shear
  along the trace t = (cos φ, 0, sin φ) and along y. φ = 90° is a plane going straight down
  from the surface. The search (``search_planes``) scores every 5° first, then every Δφ
  around each point's best 5° plane (SWT; Fatemi–Socie, whose plane of maximum γ_a may jump
  between two near-equal peaks, scores every Δφ).
- **Life**: the Basquin–Coffin–Manson form Σ_i A_i (2N)^{e_i} (all e_i < 0) inverted for N
  by bisection on log(2N) ∈ [0, 30 ln 10] (60 halvings: 2N to 1e-15 relative).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .history import StressHistory

__all__ = [
    "AMPLITUDE_METHODS",
    "hydrostatic",
    "deviatoric_coordinates",
    "shear_amplitude",
    "minimum_ball",
    "Ball",
    "PlaneFamily",
    "plane_family",
    "invert_life",
]

AMPLITUDE_METHODS = ("chord", "ball")
_ROOT2 = np.sqrt(2.0)


def hydrostatic(history: StressHistory) -> np.ndarray:
    """σ_H = (σ_xx + σ_yy + σ_zz)/3 (MPa), shape (n_instants, n_points)."""
    return history.tensor[..., :3].sum(axis=-1) / 3.0


def deviatoric_coordinates(history: StressHistory) -> np.ndarray:
    """v (MPa), shape (n_instants, n_points, 6), with |v|² = J2 (module docstring)."""
    tensor = history.tensor
    normal = tensor[..., :3] - hydrostatic(history)[..., None]
    return np.concatenate([normal, _ROOT2 * tensor[..., 3:]], axis=-1) / _ROOT2


def _half_longest_chord(coordinates: np.ndarray, budget: int = 1 << 18) -> np.ndarray:
    """max over instant pairs of |v(t1) − v(t2)|/2, shape (n_points,): the pair distances
    from the Gram matrices of the paths centred on their mean (against cancellation), in
    chunks of points holding at most ``budget`` pair values (2 MB arrays: faster than larger
    chunks, which leave the cache, and the same result: chunking changes no arithmetic)."""
    n_instants, n_points, _ = coordinates.shape
    centred = coordinates - coordinates.mean(axis=0)
    paths = np.ascontiguousarray(centred.transpose(1, 0, 2))  # (n_points, n_instants, k)
    squared = np.empty(n_points)
    size = max(1, budget // (n_instants * n_instants))
    for start in range(0, n_points, size):
        chunk = paths[start : start + size]
        gram = chunk @ chunk.transpose(0, 2, 1)
        norms = np.einsum("ptt->pt", gram)
        distance = norms[:, :, None] + norms[:, None, :] - 2.0 * gram
        squared[start : start + size] = distance.max(axis=(1, 2))
    return 0.5 * np.sqrt(np.clip(squared, 0.0, None))


@dataclass(frozen=True)
class Ball:
    """Minimum circumscribed ball of the deviatoric path: ``centre`` (n_points, 6) in the
    coordinates v (MPa), ``radius`` (n_points,) (MPa), ``iterations`` done and whether every
    point reached the relative gap ``tolerance`` (``converged``)."""

    centre: np.ndarray
    radius: np.ndarray
    iterations: int
    converged: bool
    tolerance: float


def minimum_ball(
    coordinates: np.ndarray, *, tolerance: float = 1e-10, max_iterations: int = 200_000
) -> Ball:
    """Minimum ball enclosing the points ``coordinates[:, p]`` for every p (shape
    (n_instants, n_points, k)), by pairwise Frank–Wolfe steps on the dual
    max_λ Σ λ_t |v_t|² − |Σ λ_t v_t|² over the simplex (module docstring). A point stops
    when its farthest instant lies within the relative ``tolerance`` of the dual value (the
    squared radius), or within 1e-13 of the path's squared size (rounding). Most points stop
    within a few tens of steps; near-duplicate supporting instants (both sides of a load
    reversal) slow the linear rate of a few: 7,857 steps for the slowest point of a 3-D
    fretting cycle (sphere, 128², 80 instants, ``tests/data/slow_minimum_ball.npy``). Only
    the points still open are stepped, so those cost little."""
    n_instants, n_points, _ = coordinates.shape
    weights = np.zeros((n_points, n_instants))
    weights[:, 0] = 1.0
    floor = 1e-13 * np.einsum("tpk,tpk->tp", coordinates, coordinates).max(axis=0)
    active = np.arange(n_points)
    path, own, low = coordinates, weights.copy(), floor  # the open points, compacted
    iterations = 0
    while active.size and iterations < max_iterations:
        iterations += 1
        done = _frank_wolfe_step(path, own, tolerance, low)
        if done.any():  # finished: keep their weights, step the others on compact arrays
            weights[active[done]] = own[done]
            keep = ~done
            active, path, own, low = active[keep], path[:, keep], own[keep], low[keep]
    weights[active] = own
    centre = np.einsum("pt,tpk->pk", weights, coordinates)
    offset = coordinates - centre[None]
    radius = np.sqrt(np.einsum("tpk,tpk->tp", offset, offset).max(axis=0))
    return Ball(centre, radius, iterations, active.size == 0, tolerance)


def _frank_wolfe_step(coordinates, weights, tolerance, floor) -> np.ndarray:
    """One pairwise step of the dual ``weights`` (n_points, n_instants) of the paths
    ``coordinates`` (n_instants, n_points, k), in place for the points not yet converged:
    weight moves from the nearest supporting instant k to the farthest instant j by the
    exact line search γ = (d_j² − d_k²)/(2|v_j − v_k|²), clipped to [0, λ_k]. Returns which
    of the points had already converged (module docstring, ``minimum_ball``)."""
    rows = np.arange(weights.shape[0])
    centre = np.einsum("pt,tpk->pk", weights, coordinates)
    offset = coordinates - centre[None]
    squared = np.einsum("tpk,tpk->pt", offset, offset)
    value = np.einsum("pt,pt->p", weights, squared)
    far = np.argmax(squared, axis=1)
    near = np.argmin(np.where(weights > 0.0, squared, np.inf), axis=1)
    far_squared, near_squared = squared[rows, far], squared[rows, near]
    done = far_squared <= value * (1.0 + tolerance) + floor
    chord = coordinates[far, rows] - coordinates[near, rows]
    chord_squared = np.einsum("pk,pk->p", chord, chord)
    step = np.divide(
        far_squared - near_squared,
        2.0 * chord_squared,
        where=chord_squared > 0.0,
        out=np.zeros(rows.size),
    )
    step = np.clip(step, 0.0, weights[rows, near]) * ~done
    weights[rows, near] -= step
    weights[rows, far] += step
    return done


def shear_amplitude(history: StressHistory, method: str = "chord") -> np.ndarray:
    """√J2,a (MPa), shape (n_points,), by ``method`` "chord" or "ball" (module docstring)."""
    coordinates = deviatoric_coordinates(history)
    if method == "chord":
        return _half_longest_chord(coordinates)
    if method == "ball":
        ball = minimum_ball(coordinates)
        if not ball.converged:
            raise RuntimeError(
                f"minimum ball of the deviatoric path not converged in {ball.iterations} "
                f"iterations (relative gap {ball.tolerance:g})"
            )
        return ball.radius
    raise ValueError(f"amplitude_method must be one of {AMPLITUDE_METHODS}, got {method!r}")


@dataclass(frozen=True)
class PlaneFamily:
    """Planes containing the y axis (module docstring): trace angles ``angle`` (deg, shape
    (n_planes,)), and the weights that resolve a stress vector in ``COMPONENTS`` order onto
    them: ``normal`` σ_nn, ``shear_trace`` σ_nt along the trace, ``shear_y`` σ_ny; each of
    shape (6, n_planes), so that ``history.tensor @ weights`` resolves every instant and
    point at once."""

    angle: np.ndarray
    normal: np.ndarray
    shear_trace: np.ndarray
    shear_y: np.ndarray


def _resolving_weights(normal: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Weights w (6, n) with w · σ = n · σ · d for symmetric σ in ``COMPONENTS`` order."""
    n, d = normal, direction
    return np.stack(
        [
            n[0] * d[0],
            n[1] * d[1],
            n[2] * d[2],
            n[1] * d[2] + n[2] * d[1],
            n[0] * d[2] + n[2] * d[0],
            n[0] * d[1] + n[1] * d[0],
        ]
    )


def _plane_weights(angle: np.ndarray) -> PlaneFamily:
    """The planes of trace angles ``angle`` (deg, any shape); weights (6, *angle.shape)."""
    phi = np.radians(angle)
    zero, one = np.zeros_like(phi), np.ones_like(phi)
    normal = np.stack([-np.sin(phi), zero, np.cos(phi)])
    trace = np.stack([np.cos(phi), zero, np.sin(phi)])
    y_axis = np.stack([zero, one, zero])
    return PlaneFamily(
        angle=angle,
        normal=_resolving_weights(normal, normal),
        shear_trace=_resolving_weights(normal, trace),
        shear_y=_resolving_weights(normal, y_axis),
    )


# The finest plane step: 1800 planes per point and cycle. Finer steps multiply the search's
# cost (minutes per case at 1e-3°) without changing a critical-plane value by more than the
# scatter of the fatigue constants it is compared with.
MIN_PLANE_STEP = 0.1  # degrees


def check_plane_step(step_degrees: float) -> float:
    """``step_degrees`` if it divides 180° and lies in [:data:`MIN_PLANE_STEP`, 90]."""
    if not MIN_PLANE_STEP <= step_degrees <= 90.0 or not float(180.0 / step_degrees).is_integer():
        raise ValueError(
            f"plane_step must divide 180 degrees and lie in [{MIN_PLANE_STEP:g}, 90] "
            f"(finer steps cost minutes per case and change no result beyond the scatter "
            f"of the fatigue constants), got {step_degrees!r}"
        )
    return float(step_degrees)


def plane_family(step_degrees: float = 1.0) -> PlaneFamily:
    """The planes φ = 0, Δφ, … < 180° (module docstring) for Δφ = ``step_degrees``."""
    return _plane_weights(np.arange(0.0, 180.0, check_plane_step(step_degrees)))


class ResolvedStress:
    """A stress history (n_instants, n_points, 6) resolved on planes, each resolution computed
    on first use: ``normal()``, ``shear_trace()``, ``shear_y()`` of shape
    (n_instants, n_points, n_planes). The planes are common to all points (weights
    (6, n_planes)) or per point (weights (6, n_points, n_planes))."""

    def __init__(self, tensor: np.ndarray, planes: PlaneFamily):
        self.tensor, self.planes, self._cache = tensor, planes, {}

    def _resolve(self, name: str) -> np.ndarray:
        if name not in self._cache:
            weights = getattr(self.planes, name)
            if weights.ndim == 2:
                self._cache[name] = self.tensor @ weights
            else:
                self._cache[name] = np.einsum("tpc,cpk->tpk", self.tensor, weights)
        return self._cache[name]

    def normal(self) -> np.ndarray:
        return self._resolve("normal")

    def shear_trace(self) -> np.ndarray:
        return self._resolve("shear_trace")

    def shear_y(self) -> np.ndarray:
        return self._resolve("shear_y")


COARSE_STEP = 5.0  # degrees: the first pass of the plane search


def search_planes(
    history: StressHistory, score, step: float, *, two_pass: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """The maximum over planes of ``score(ResolvedStress) -> (n_points, n_planes)`` at every
    point, and its trace angle (deg): a first pass every ``COARSE_STEP`` (when ``step``
    divides it), then every ``step`` within ± (COARSE_STEP − step) of each point's best
    coarse plane. A maximum in another coarse interval is missed only if its coarse sample
    scored lower than the best one; it then exceeds that sample by at most the score's
    variation over COARSE_STEP/2. ``two_pass=False``: every ``step`` at once (for scores
    that jump between planes). Chunks of points bound the memory (``point_chunks``)."""
    step = check_plane_step(step)
    divides = (COARSE_STEP / step).is_integer()
    coarse = COARSE_STEP if two_pass and step < COARSE_STEP and divides else step
    family = plane_family(coarse)
    reach = round(coarse / step) - 1
    offsets = step * np.arange(-reach, reach + 1)
    value, angle = np.empty(history.n_points), np.empty(history.n_points)
    for chunk in point_chunks(history, 3 * max(family.angle.size, offsets.size)):
        tensor = history.tensor[:, chunk]
        best = family.angle[np.argmax(score(ResolvedStress(tensor, family)), axis=1)]
        if reach == 0:
            candidates = np.broadcast_to(family.angle, (best.size, family.angle.size))
        else:
            candidates = np.mod(best[:, None] + offsets[None, :], 180.0)
        scores = score(ResolvedStress(tensor, _plane_weights(candidates)))
        index = np.argmax(scores, axis=1)[:, None]
        value[chunk] = np.take_along_axis(scores, index, axis=1)[:, 0]
        angle[chunk] = np.take_along_axis(candidates, index, axis=1)[:, 0]
    return value, angle


def invert_life(value, coefficients, exponents) -> np.ndarray:
    """N (cycles) solving value = Σ_i A_i (2N)^{e_i} (A_i = ``coefficients`` > 0, e_i =
    ``exponents`` < 0), elementwise; N = inf where value ≤ the right side at 2N = 1e30 (no
    failure predicted, including value ≤ 0) and N = 0.5 where value ≥ the right side at 2N = 1."""
    value = np.asarray(value, dtype=float)
    coefficients = np.asarray(coefficients, dtype=float)
    exponents = np.asarray(exponents, dtype=float)
    if np.any(coefficients <= 0.0) or np.any(exponents >= 0.0):
        raise ValueError(
            f"life curve needs coefficients > 0 and exponents < 0, got {coefficients.tolist()} "
            f"and {exponents.tolist()}"
        )

    def curve(log_reversals):
        return np.sum(coefficients * np.exp(np.multiply.outer(log_reversals, exponents)), -1)

    upper = 30.0 * np.log(10.0)
    low = np.zeros_like(value)
    high = np.full_like(value, upper)
    for _ in range(60):
        middle = 0.5 * (low + high)
        above = curve(middle) > value
        low = np.where(above, middle, low)
        high = np.where(above, high, middle)
    life = 0.5 * np.exp(0.5 * (low + high))
    life = np.where(value >= curve(np.zeros(1))[0], 0.5, life)
    return np.where(value <= curve(np.full(1, upper))[0], np.inf, life)


def point_chunks(history: StressHistory, planes: int, budget: int = 1 << 20):
    """Slices of the points such that one chunk resolved on all planes holds at most
    ``budget`` values (n_instants × chunk × planes): the memory bound of the plane search
    (8 MB arrays; larger chunks are slower, out of the cache, and give the same result)."""
    size = max(1, budget // max(1, history.n_instants * planes))
    return [slice(start, start + size) for start in range(0, history.n_points, size)]


def resolve(tensor: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Stresses (n_instants, n_points, 6) resolved on planes by ``weights`` (6, n_planes):
    shape (n_instants, n_points, n_planes), one matrix product."""
    return tensor @ weights


def cycle_range(values: np.ndarray) -> np.ndarray:
    """Half the range over the instants (axis 0): the amplitude (max − min)/2."""
    return 0.5 * (values.max(axis=0) - values.min(axis=0))
