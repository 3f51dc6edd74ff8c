"""Threshold searches: where along one parameter a summary column crosses a target.

A ``[search]`` section asks, for every combination of the ``[sweep]``, for the value of one
continuous parameter (any sweepable key, e.g. ``loading.amplitude`` in mm) at which a summary
column changes side:

- **categorical** column (text, e.g. ``slip_regime``): the boundary between the parameter
  values whose column equals ``target`` (e.g. ``"gross"``) and those where it does not;
- **numeric** column (e.g. ``q_amplitude`` in N): the root of ``f(x) = column(x) − target``.

The method, as a bracketing root finder over cases (each evaluation is one case of the study):

1. **bracket check**: both ends ``low`` and ``high`` are evaluated (at once); they must lie on
   different sides (categorical: one equals ``target``, the other not; numeric: ``f`` changes
   sign, or is exactly zero at an end). Otherwise the search ends ``not-bracketed`` and
   reports both ends' values; nothing is guessed.
2. **iteration** on the bracket [lower, upper] (lower < upper):

   - categorical: bisection, x = (lower + upper)/2;
   - numeric: the Illinois variant of regula falsi (Dowell & Jarratt, BIT 11 (1971) 168):
     x = lower − f_lower (upper − lower)/(f_upper − f_lower), where the value of an end that
     has stayed in the bracket for two steps in a row is halved; safeguarded like Brent's
     method (Brent, *Algorithms for Minimization without Derivatives*, 1973, ch. 4): x is kept
     at least tol/2 inside the bracket, and when two steps have not halved the bracket the
     next step bisects, so the search never takes more than about twice bisection's steps.

3. **stop** when the bracket is narrow enough, tol = atol + rtol·|midpoint|:
   categorical: upper − lower ≤ 2 tol, threshold = midpoint (|error| ≤ tol);
   numeric: upper − lower ≤ tol, threshold = the secant root of the final bracket with the
   true values of f (inside the bracket, |error| ≤ tol).

A search that needs more than ``max_steps`` cases ends ``not-converged`` (threshold NaN, the
bracket reported); one whose case failed, or whose column is missing or NaN, ends ``failed``.

The state of a search is a pure function of the values it has been given in order: replaying
the completed cases of a results file (:meth:`Search.replay`) proposes the same next case and
ends with the same threshold, bit for bit, as an uninterrupted run.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from engine.schema import (
    COLUMN_UNITS,
    INTEGER_COLUMNS,
    REGIONS,
    SUMMARY_COLUMNS,
    TEXT_COLUMNS,
    CaseStatus,
)
from engine.solvers.fretting import REGIME_NAMES

from .fatigue import fatigue_column_specs
from .plan import Case, Plan, setting_names
from .plan import _format as format_value
from .settings.checks import LIMITS
from .settings.sections import MISSING, StudyConfigError
from .units import SWEEPABLE

__all__ = [
    "SearchSpec",
    "Search",
    "SearchResult",
    "SearchStatus",
    "StepFailure",
    "SearchCampaign",
    "search_tolerance",
]


class SearchStatus:
    """How a search ended (text, stored in the thresholds table)."""

    CONVERGED = "converged"  # bracket within tolerance: threshold given
    NOT_BRACKETED = "not-bracketed"  # low and high on the same side
    NOT_CONVERGED = "not-converged"  # max_steps cases without reaching the tolerance
    FAILED = "failed"  # a case failed or its column is missing / NaN
    UNFINISHED = "unfinished"  # the run stopped before the search ended (rerun to resume)


METHODS = ("bisection", "illinois")
ID_RESOLUTION = 1e-8  # finest relative tolerance: case ids carry 10 significant digits
MAX_STEPS = int(LIMITS["search.max_steps"].maximum)  # cases per search (a bound on typos)


@dataclass(frozen=True)
class SearchSpec:
    """A validated ``[search]`` section.

    Parameters
    ----------
    parameter : str
        Dotted sweepable key searched along (continuous, in its own units).
    low, high : float
        The bracket's ends, low < high, in the parameter's units.
    column : str
        The deciding summary column.
    target : float or str
        Numeric: the column's value at the threshold (the column's units). Text: the value
        that marks the far side of the boundary (e.g. ``"gross"``).
    rtol, atol : float
        Tolerance on the parameter: tol = atol + rtol·|x| (atol in the parameter's units).
    method : str
        ``"bisection"`` or ``"illinois"`` (numeric columns only); default: Illinois for a
        numeric target, bisection for a text one.
    max_steps : int
        Cases one search may take, both ends included.
    """

    parameter: str
    low: float
    high: float
    column: str
    target: float | str
    rtol: float = 0.0
    atol: float = 0.0
    method: str = ""
    max_steps: int = 60

    def __post_init__(self) -> None:
        if not self.method:
            object.__setattr__(self, "method", "bisection" if self.categorical else "illinois")

    @property
    def categorical(self) -> bool:
        """True when the column is compared with a text ``target``."""
        return isinstance(self.target, str)

    def problems(self) -> list[tuple[str, Any, str]]:
        """(key, value, problem) of every inconsistency; empty when the spec is usable."""
        found = []
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            found.append(("high", self.high, f"must be finite and greater than low = {self.low}"))
        for key in ("rtol", "atol"):
            if not getattr(self, key) >= LIMITS[f"search.{key}"].minimum:
                found.append((key, getattr(self, key), "must be ≥ 0"))
        if not self.rtol + self.atol > 0.0:
            found.append(("rtol", self.rtol, "rtol and atol must be ≥ 0, one of them > 0"))
        span = max(abs(self.low), abs(self.high))
        if (
            0.0 < self.rtol + self.atol
            and self.rtol < ID_RESOLUTION
            and self.atol < ID_RESOLUTION * span
        ):
            found.append(
                (
                    "rtol",
                    self.rtol,
                    f"rtol ≥ {ID_RESOLUTION:g} or atol ≥ {ID_RESOLUTION:g}·max(|low|, "
                    "|high|): finer steps would share a case id (10 significant digits)",
                )
            )
        if self.rtol >= LIMITS["search.rtol"].maximum:
            found.append(("rtol", self.rtol, "must be < 0.5 (a relative tolerance on x)"))
        if not (math.isfinite(self.atol) and self.atol < self.high - self.low):
            found.append(
                ("atol", self.atol, "must be finite and below the bracket's width high − low")
            )
        if self.method not in METHODS:
            found.append(("method", self.method, f"must be one of {', '.join(METHODS)}"))
        elif self.categorical and self.method != "bisection":
            found.append(("method", self.method, "a text target is searched by bisection"))
        if not (
            isinstance(self.max_steps, int) and LIMITS["search.max_steps"].holds(self.max_steps)
        ):
            found.append(
                (
                    "max_steps",
                    self.max_steps,
                    f"must be an integer in [3, {MAX_STEPS}] (bisection halves the bracket per "
                    "case: the finest tolerance, 1e-8 of the bracket, takes 27)",
                )
            )
        if not self.categorical and not math.isfinite(self.target):
            found.append(("target", self.target, "must be finite"))
        return found


def search_tolerance(spec: SearchSpec, x: float) -> float:
    """tol = atol + rtol·|x| (parameter units)."""
    return spec.atol + spec.rtol * abs(x)


@dataclass(frozen=True)
class StepFailure:
    """A case of a search that gave no usable value (failed, or its column NaN/missing)."""

    message: str


@dataclass
class SearchResult:
    """Where a search stands, or how it ended.

    ``threshold`` (parameter units) is NaN unless ``status`` is converged; ``lower`` and
    ``upper`` are the final bracket (the ends when the bracket check failed), ``lower_value``
    and ``upper_value`` the column there; ``steps`` the cases evaluated; ``evaluations`` the
    (parameter, column value) pairs in the order they were taken (the ends low, high first).
    """

    status: str
    threshold: float = math.nan
    lower: float = math.nan
    upper: float = math.nan
    lower_value: Any = math.nan
    upper_value: Any = math.nan
    steps: int = 0
    message: str = ""
    evaluations: list[tuple[float, Any]] = field(default_factory=list)

    @property
    def converged(self) -> bool:
        return self.status == SearchStatus.CONVERGED


@dataclass
class _End:
    """One end of the bracket: parameter x, column value, f (numeric: value − target) and the
    weight of f in the Illinois interpolation."""

    x: float
    value: Any
    f: float
    weight: float = 1.0


class Search:
    """One threshold search; feed it column values, it proposes the next parameter values.

    ``pending()`` lists the parameter values to evaluate now (both ends first, then one at a
    time); ``record(x, value)`` gives the column value (or a :class:`StepFailure`) at one of
    them; ``result`` says where the search stands. Deterministic: the same values in the same
    order give the same proposals and the same threshold, bit for bit.
    """

    def __init__(self, spec: SearchSpec) -> None:
        if spec.problems():
            key, value, problem = spec.problems()[0]
            raise ValueError(f"search {key} = {value!r}: {problem}")
        self.spec = spec
        self._pending: list[float] = [spec.low, spec.high]
        self._ends: dict[float, Any] = {}  # the two ends' values while the check waits
        self._lower: _End | None = None
        self._upper: _End | None = None
        self._widths: list[float] = []  # bracket widths after each step, for the safeguard
        self._moved: list[str] = []  # which end each step replaced ("lower" / "upper")
        self._result = SearchResult(SearchStatus.UNFINISHED)

    # ------------------------------------------------------------------ interface
    @property
    def finished(self) -> bool:
        return self._result.status != SearchStatus.UNFINISHED

    @property
    def result(self) -> SearchResult:
        return self._result

    def pending(self) -> tuple[float, ...]:
        """Parameter values whose column the search waits for (empty once finished)."""
        return () if self.finished else tuple(self._pending)

    def record(self, x: float, value: Any) -> None:
        """The column value at ``x`` (one of :meth:`pending`), or a :class:`StepFailure`."""
        if x not in self._pending:
            raise ValueError(f"the search did not ask for {self.spec.parameter} = {x!r}")
        self._pending.remove(x)
        self._result.steps += 1
        if self._lower is None:  # the bracket check waits for both ends, whatever they hold
            self._ends[x] = value
            if not self._pending:
                self._result.evaluations.extend(sorted(self._ends.items()))
                self._check_bracket()
            return
        self._result.evaluations.append((x, value))
        if not self._failed(x, value):
            self._step(x, value)

    def _failed(self, x: float, value: Any) -> bool:
        """Finish as failed when ``value`` is unusable; True then."""
        problem = self._unusable(value)
        if problem:
            self._finish(SearchStatus.FAILED, message=f"{self.spec.parameter} = {x!r}: {problem}")
        return bool(problem)

    def replay(self, lookup: Callable[[float], Any]) -> tuple[float, ...]:
        """Feed every pending value that ``lookup(x)`` knows (a completed case: its column
        value or a :class:`StepFailure`; unknown: ``None``) until the search needs a case
        not yet computed; returns those parameter values (empty: finished)."""
        while not self.finished:
            known = [(x, lookup(x)) for x in self.pending()]
            known = [(x, value) for x, value in known if value is not None]
            if not known:
                break
            for x, value in known:
                self.record(x, value)
        return self.pending()

    # ------------------------------------------------------------------ the method
    def _unusable(self, value: Any) -> str:
        if isinstance(value, StepFailure):
            return value.message
        if self.spec.categorical:
            if not isinstance(value, str) or not value:
                return f"column {self.spec.column!r} has no text value ({value!r})"
            return ""
        try:
            number = float(value)
        except (TypeError, ValueError):
            return f"column {self.spec.column!r} is not a number ({value!r})"
        if not math.isfinite(number):
            return f"column {self.spec.column!r} is {value!r}"
        return ""

    def _f(self, value: Any) -> float:
        """Numeric: value − target; categorical: +1 on the target side, −1 elsewhere."""
        if self.spec.categorical:
            return 1.0 if value == self.spec.target else -1.0
        return float(value) - float(self.spec.target)

    def _check_bracket(self) -> None:
        low, high = self.spec.low, self.spec.high
        if self._failed(low, self._ends[low]) or self._failed(high, self._ends[high]):
            return
        lower = _End(low, self._ends[low], self._f(self._ends[low]))
        upper = _End(high, self._ends[high], self._f(self._ends[high]))
        self._lower, self._upper = lower, upper
        for end in (lower, upper):
            if end.f == 0.0 and not self.spec.categorical:  # the target is met at an end
                self._finish(SearchStatus.CONVERGED, threshold=end.x)
                return
        if (lower.f > 0.0) == (upper.f > 0.0):
            self._finish(
                SearchStatus.NOT_BRACKETED,
                message=(
                    f"{self.spec.column} is {lower.value!r} at {self.spec.parameter} = {low!r} "
                    f"and {upper.value!r} at {high!r}: both on the same side of "
                    f"{self.spec.target!r}"
                ),
            )
            return
        self._widths.append(high - low)
        self._advance()

    def _step(self, x: float, value: Any) -> None:
        f = self._f(value)
        if f == 0.0 and not self.spec.categorical:
            self._finish(SearchStatus.CONVERGED, threshold=x)
            return
        if (f > 0.0) == (self._lower.f > 0.0):
            self._lower = _End(x, value, f)
            self._moved.append("lower")
        else:
            self._upper = _End(x, value, f)
            self._moved.append("upper")
        if len(self._moved) >= 2 and self._moved[-1] == self._moved[-2]:
            # the other end stayed twice in a row: halve its weight (Illinois); an end that
            # was just replaced starts again with weight 1
            stayed = self._upper if self._moved[-1] == "lower" else self._lower
            stayed.weight *= 0.5
        self._widths.append(self._upper.x - self._lower.x)
        self._advance()

    def _advance(self) -> None:
        """Finish when the bracket is narrow enough, else propose the next x."""
        lower, upper = self._lower, self._upper
        width = upper.x - lower.x
        middle = 0.5 * (lower.x + upper.x)
        tol = search_tolerance(self.spec, middle)
        categorical = self.spec.categorical
        if width <= (2.0 * tol if categorical else tol):
            self._finish(SearchStatus.CONVERGED, threshold=self._estimate())
            return
        if self._result.steps >= self.spec.max_steps:
            self._finish(
                SearchStatus.NOT_CONVERGED,
                message=f"{self.spec.max_steps} cases (max_steps) left a bracket of {width!r}",
            )
            return
        self._pending = [self._next_x(middle, tol)]

    def _next_x(self, middle: float, tol: float) -> float:
        if self.spec.method == "bisection" or self._stalled():
            return middle
        lower, upper = self._lower, self._upper
        f_lower, f_upper = lower.weight * lower.f, upper.weight * upper.f
        x = lower.x - f_lower * (upper.x - lower.x) / (f_upper - f_lower)
        margin = 0.5 * tol
        return min(max(x, lower.x + margin), upper.x - margin)

    def _stalled(self) -> bool:
        """Brent's safeguard: the last two steps did not halve the bracket."""
        widths = self._widths
        return len(widths) >= 3 and widths[-1] > 0.5 * widths[-3]

    def _estimate(self) -> float:
        """The threshold in the final bracket: midpoint (categorical), secant root with the
        true values of f (numeric)."""
        lower, upper = self._lower, self._upper
        if self.spec.categorical:
            return 0.5 * (lower.x + upper.x)
        return lower.x - lower.f * (upper.x - lower.x) / (upper.f - lower.f)

    def _finish(self, status: str, *, threshold: float = math.nan, message: str = "") -> None:
        result = self._result
        result.status, result.threshold, result.message = status, threshold, message
        if self._lower is not None:
            result.lower, result.upper = self._lower.x, self._upper.x
            result.lower_value, result.upper_value = self._lower.value, self._upper.value
        else:
            result.lower, result.upper = self.spec.low, self.spec.high
            values = {x: _plain(value) for x, value in self._ends.items()}
            result.lower_value = values.get(self.spec.low, math.nan)
            result.upper_value = values.get(self.spec.high, math.nan)
        self._pending = []


def _plain(value: Any) -> Any:
    """A column value for the table: NaN for a :class:`StepFailure`."""
    return math.nan if isinstance(value, StepFailure) else value


# ---------------------------------------------------------------------- the study's searches
class SearchCampaign:
    """Every search of a study: one per case of the ``[sweep]`` plan (each combination of
    its values), each step a :class:`~engine.study.plan.Case` with the searched parameter
    added to its settings.

    A step's case id is the combination's id with ``_<name><x>`` appended (``name``: the last
    part of the dotted parameter, as for swept keys), e.g. ``mu0.5_w0_b0_load100_amplitude0.004``.
    Rank 0 owns the campaign: :meth:`start` replays the completed cases of an existing
    results file and returns the cases to run now; :meth:`record` takes an outcome's row and
    returns the cases it unlocks; :meth:`cases` lists every case so far in the canonical
    order (search by search, steps in the order taken), the same after any interruption.
    """

    def __init__(self, spec: SearchSpec, plan: Plan, swept_keys: tuple[str, ...] = ()) -> None:
        self.spec = spec
        self.bases = plan.cases
        self.searches = [Search(spec) for _ in plan.cases]
        self.name = setting_names((*swept_keys, spec.parameter))[spec.parameter]
        self._steps: dict[str, tuple[int, float]] = {}  # case id -> (search number, x)
        self._cases: dict[str, Case] = {}

    @property
    def finished(self) -> bool:
        return all(search.finished for search in self.searches)

    def case_for(self, number: int, x: float) -> Case:
        """The case of search ``number`` at parameter value ``x`` (parameter units)."""
        base = self.bases[number]
        case_id = f"{base.case_id}_{self.name}{format_value(x)}"
        known = self._steps.get(case_id)
        if known is not None and known != (number, x):
            raise ValueError(
                f"two steps of a search share the case id {case_id!r} "
                f"({self.spec.parameter} = {known[1]!r} and {x!r}): loosen rtol/atol"
            )
        if case_id not in self._cases:
            settings = (*base.settings, (self.spec.parameter, x))
            case = dataclasses.replace(base, case_id=case_id, settings=settings)
            self._steps[case_id] = (number, x)
            self._cases[case_id] = case
        return self._cases[case_id]

    def start(self, rows: Mapping[str, Mapping[str, Any]] | None = None) -> list[Case]:
        """Replay every search on the stored rows (case id -> summary row, e.g. of the results
        file being resumed: its completed cases) and return the cases to run now, search by
        search."""
        rows = rows or {}
        todo = []
        for number, search in enumerate(self.searches):

            def lookup(x: float, number: int = number) -> Any:
                row = rows.get(self.case_for(number, x).case_id)
                if row is None or row.get("status") != CaseStatus.COMPLETED:
                    return None  # a failed case is run again on resume, as in any study
                return self._stored_value(row, x)

            todo.extend(self.case_for(number, x) for x in search.replay(lookup))
        return todo

    def record(self, case_id: str, row: Mapping[str, Any]) -> list[Case]:
        """The outcome of one step (its summary row, status included); returns the cases
        its search newly asks for (none when it has ended or waits for its other end)."""
        number, x = self._steps[case_id]
        value = self._stored_value(row, x)
        if value is None:
            raise ValueError(f"case {case_id!r} has not completed (status {row.get('status')})")
        search = self.searches[number]
        asked = set(search.pending()) - {x}  # handed out already
        search.record(x, value)
        return [self.case_for(number, new) for new in search.pending() if new not in asked]

    def _stored_value(self, row: Mapping[str, Any] | None, x: float) -> Any:
        """A step's value from its summary row: the column, a :class:`StepFailure` for a
        failed case, None while it is not done (or holds another value of the parameter)."""
        if row is None or row.get(self.spec.parameter) != x:
            return None
        status = row.get("status")
        if status == CaseStatus.FAILED:
            return StepFailure(f"case {row.get('case_id')} failed")
        if status != CaseStatus.COMPLETED:
            return None
        return row.get(self.spec.column, math.nan)

    def cases(self) -> list[Case]:
        """Every case created so far, search by search in the order its steps were taken
        (the pending ones last), with ``index`` its position."""
        ordered = []
        for number, search in enumerate(self.searches):
            xs = [x for x, _ in search.result.evaluations] + list(search.pending())
            ordered.extend(self.case_for(number, x) for x in xs)
        return [dataclasses.replace(case, index=i) for i, case in enumerate(ordered)]

    def table(self) -> list[dict[str, Any]]:
        """One row per search (plan order): the combination's parameters (as in the summary),
        then threshold, lower, upper (parameter units), lower_value, upper_value (the
        column's), steps, status, message."""
        rows = []
        for base, search in zip(self.bases, self.searches, strict=True):
            result = search.result
            row = {key: value for key, value in base.parameters().items() if key != "index"}
            row.update(
                threshold=result.threshold,
                lower=result.lower,
                upper=result.upper,
                lower_value=result.lower_value,
                upper_value=result.upper_value,
                steps=result.steps,
                status=result.status,
                message=result.message,
            )
            rows.append(row)
        return rows


# ---------------------------------------------------------------------- the [search] section
SEARCH_KEYS = ("parameter", "low", "high", "column", "target", "rtol", "atol", "method")
SEARCH_KEYS += ("max_steps",)
#: Sweepable keys that take integers: no threshold between two neighbours to search for.
INTEGER_KEYS = ("mesh.n", "loading.steps", "loading.cycles", "subsurface.layers", "solver.maxiter")


#: Numeric columns whose values the physics bounds: (lowest, highest, what the column is). A
#: target outside is never reached, whatever the parameter.
_FRACTION = (0.0, 1.0, "a fraction, in [0, 1]")
_NONNEGATIVE = (0.0, math.inf, "a size, never negative")
COLUMN_RANGES: dict[str, tuple[float, float, str]] = {
    "stick_fraction": _FRACTION,
    **dict.fromkeys(
        (
            "load", "p0", "max_wear_depth", "wear_volume", "contact_radius", "centre_pressure",
            "wear_severity", "runtime_s", "q_amplitude", "displacement_amplitude",
            "energy_per_cycle", "scar_depth", "scar_width", "scar_area", "pad_wear_depth",
            "real_area_fraction", "largest_spot_area", "real_mean_pressure",
            "real_peak_pressure", "rms_height", "rms_slope", "rms_height_worn", "rms_slope_worn",
        ),
        _NONNEGATIVE,
    ),
}  # fmt: skip


def column_range(column: str) -> tuple[float, float, str] | None:
    """(lowest, highest, why) of a numeric summary column's values, where they are bounded:
    :data:`COLUMN_RANGES`, a von Mises stress (``vm_*``) and a depth (``vm_*_z``) never
    negative; None for a column that can take any value (coordinates x, y, an approach)."""
    if column in COLUMN_RANGES:
        return COLUMN_RANGES[column]
    if column.startswith("vm_") and column.endswith("_z"):
        return (0.0, math.inf, "a depth below the surface, never negative")
    if column.startswith("vm_") and not column.endswith(("_x", "_y")):
        return (0.0, math.inf, "a von Mises stress, never negative")
    return None


def parse_search(source: str, table: Any, swept_keys: tuple[str, ...] = ()) -> SearchSpec:
    """Validate the ``[search]`` table of a study file into a :class:`SearchSpec`; errors
    name the key and its value (:class:`~engine.study.config.StudyConfigError`)."""
    # the values a text column can take: a target among none of them is never reached
    text_values = {"slip_regime": REGIME_NAMES, "peak_region": REGIONS, "deep_region": REGIONS}

    def error(key: str, value: Any, problem: str) -> StudyConfigError:
        return StudyConfigError(source, f"search.{key}", value, problem)

    if not isinstance(table, dict):
        raise StudyConfigError(source, "search", table, "must be a table ([search])")
    for key, value in table.items():
        if key not in SEARCH_KEYS:
            raise error(key, value, f"unknown key (known: {', '.join(SEARCH_KEYS)})")
    for key in SEARCH_KEYS[:5]:
        if key not in table:
            raise error(key, MISSING, "required key is missing")
    parameter = table["parameter"]
    if parameter not in SWEEPABLE or parameter in INTEGER_KEYS:
        known = ", ".join(key for key in SWEEPABLE if key not in INTEGER_KEYS)
        raise error("parameter", parameter, f"not a continuous sweepable key (known: {known})")
    if parameter in swept_keys:
        raise error("parameter", parameter, "is swept in [sweep]: search it or sweep it")
    for key in ("low", "high", "rtol", "atol"):
        value = table.get(key, 0.0)
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise error(key, value, "must be a number")
    column, target = table["column"], table["target"]
    known_columns = set(SUMMARY_COLUMNS) | set(COLUMN_UNITS) | set(TEXT_COLUMNS)
    known_columns |= set(fatigue_column_specs())
    if column not in known_columns - {"case_id", "status"}:
        raise error("column", column, "not a summary column")
    if column in TEXT_COLUMNS and not isinstance(target, str):
        raise error("target", target, f"{column} is a text column: the target is its text")
    values = text_values.get(column)
    if values is not None and target not in values:
        raise error(
            "target", target, f"{column} takes only {', '.join(map(repr, values))}: never reached"
        )
    if column in INTEGER_COLUMNS and not isinstance(target, str) and target < 0:
        raise error("target", target, f"{column} counts (≥ 0): a negative target is never reached")
    if column not in TEXT_COLUMNS and (
        isinstance(target, bool) or not isinstance(target, int | float)
    ):
        raise error("target", target, f"{column} is a numeric column: the target is a number")
    bounds = column_range(column)
    if bounds is not None and not bounds[0] <= target <= bounds[1]:
        raise error("target", target, f"{column} is {bounds[2]}: never reached")
    max_steps = table.get("max_steps", 60)
    if isinstance(max_steps, bool) or not isinstance(max_steps, int):
        raise error("max_steps", max_steps, "must be an integer")
    spec = SearchSpec(
        parameter=parameter,
        low=float(table["low"]),
        high=float(table["high"]),
        column=column,
        target=target if isinstance(target, str) else float(target),
        rtol=float(table.get("rtol", 0.0)),
        atol=float(table.get("atol", 0.0)),
        method=str(table.get("method", "")),
        max_steps=max_steps,
    )
    for key, value, problem in spec.problems():
        raise error(key, value, problem)
    return spec


def search_section(spec: SearchSpec) -> dict[str, Any]:
    """The ``[search]`` table of the resolved study (every key, defaults filled in)."""
    return dataclasses.asdict(spec)
