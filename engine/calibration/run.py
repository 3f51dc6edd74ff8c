"""Run a calibration: the searches of the tests inside the outer fit, then the predictions.

``run_calibration(config, comm=...)`` (called by :func:`engine.run.run_study` for a study
with a ``[calibrate]`` section; every rank calls it):

1. evaluation 0, 1, 2 … of the fit (:mod:`engine.calibration.fit`): the threshold search of
   every calibration test at the values tried (:class:`~engine.calibration.search.
   TestSearches`), residuals r = predicted/measured − 1;
2. the final evaluation: every test searched at the fitted values (the calibration tests
   again, the others predicted);
3. rank 0 writes the table (:mod:`engine.calibration.output`): ``NAME_calibration.csv`` and
   the group ``/calibration`` of the results file.

The contact solutions are kept in ``<output>.contact/`` as they are computed (one file each,
written atomically): a run that is stopped (or killed) resumes from them and repeats the
uninterrupted run exactly — the same fitted values, bit for bit, with any number of ranks.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import logging
import math
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from engine.output.calibration import calibration_csv_path, write_calibration
from engine.output.space import OutputFull
from engine.study.calibrate import TARGET_KEY
from engine.study.operators import OperatorCache
from engine.study.outcome import CaseContext
from engine.study.plan import Case, make_plan, setting_names
from engine.study.plan import _format as format_value
from engine.study.search import SearchSpec, SearchStatus

from .fit import FitFailed, FitResult, fit_values
from .search import ContactStore, Stopped, TestSearches

__all__ = ["CalibrationProblem", "CalibrationResult", "run_calibration", "contact_dir"]

#: Where a calibration reports (rank 0): INFO each fit evaluation, the dry run's line and the
#: closing lines; WARNING a stop. Quiet unless the caller configures logging (the command
#: line shows INFO on stdout, WARNING on stderr).
LOGGER = logging.getLogger(__name__)

#: Fits after which a run counts as completed (an "at-bound" fit is printed as a warning).
FIT_OK = ("converged", "at-bound", "predict-only")


def contact_dir(output: Path) -> Path:
    """``<output>.contact/``: the kept contact solutions of a calibration."""
    return output.with_name(f"{output.name}.contact")


@dataclass
class CalibrationProblem:
    """The study's tests as cases: the plan's one combination ``base`` with a test's
    settings, the fitted values and the searched parameter's value."""

    config: Any
    base: Case
    _configs: dict = field(default_factory=dict)
    _names: dict = field(default_factory=dict)
    _setup: str | None = None

    @property
    def spec(self):
        return self.config.calibrate

    @property
    def search(self) -> SearchSpec:
        return self.config.search

    @property
    def parameter(self) -> str:
        return self.search.parameter

    @property
    def column(self) -> str:
        return self.search.column

    def contact_values(self, values: dict[str, float]) -> tuple[tuple[str, float], ...]:
        """The fitted values that change the contact solution (all but ``fatigue.*`` and
        the search's target)."""
        return tuple(
            (k, float(v))
            for k, v in values.items()
            if not k.startswith("fatigue.") and k != TARGET_KEY
        )

    def store_name(self, test) -> str:
        """``id@digest`` of a test's kept contact solutions: the digest covers every section
        of the study that sets the contact (all but ``[study]``, ``[subsurface]``,
        ``[fatigue]``, ``[search]``, ``[calibrate]``) and the test's own keys, so that a
        solution kept by a study since changed (or a test of the file since edited) is
        never taken for this one."""
        if test.id not in self._names:
            if self._setup is None:
                skipped = {"study", "subsurface", "fatigue", "search", "calibrate"}
                sections = {k: v for k, v in self.config.resolved().items() if k not in skipped}
                self._setup = json.dumps(sections, sort_keys=True, default=str)
            text = self._setup + repr(test.settings)
            digest = hashlib.sha256(text.encode("utf-8")).hexdigest()[:12]
            self._names[test.id] = f"{test.id}@{digest}"
        return self._names[test.id]

    def test_settings(self, test) -> dict[str, float]:
        return dict(test.settings)

    def case(self, test, x: float, values: dict[str, float]):
        """(case, configuration) of ``test`` at parameter value ``x`` and fitted ``values``."""
        own = self.test_settings(test)
        mu = own.pop("mu1", None)
        study_values = {k: v for k, v in values.items() if k != TARGET_KEY}
        settings = (*self.base.settings, *own.items(), *study_values.items(), (self.parameter, x))
        names = setting_names((self.parameter,))
        case = dataclasses.replace(
            self.base,
            case_id=f"{test.id}_{names[self.parameter]}{format_value(x)}",
            settings=tuple(settings),
        )
        if mu is not None:
            case = dataclasses.replace(case, mu1=mu, mu2=mu)
        key = tuple(settings)
        if key not in self._configs:
            self._configs[key] = self.config.for_case(settings)
        return case, self._configs[key]

    def scale(self, test) -> float:
        """The bracket's unit for ``test``: μP with ``relative_to = "mu_load"``, else 1."""
        if self.spec.relative_to != "mu_load":
            return 1.0
        own = self.test_settings(test)
        mu = own.get("mu1", self.base.mu1)
        load = own.get("loading.load", self.config.loading.load)
        return float(mu) * float(load)

    def search_spec(self, test, values: dict[str, float]) -> SearchSpec:
        """The search of ``test``: its bracket (``relative_to``), the target (fitted or the
        ``[search]`` one)."""
        scale = self.scale(test)
        target = values.get(TARGET_KEY, self.search.target)
        return dataclasses.replace(
            self.search, low=self.search.low * scale, high=self.search.high * scale, target=target
        )


@dataclass
class CalibrationResult:
    """What a calibration ends with: one row per test, the fit, the evaluations."""

    rows: list[dict[str, Any]]
    fit: FitResult
    evaluations: list[dict[str, Any]]
    solves: int
    wall_time_s: float


def _row(problem: CalibrationProblem, test, result) -> dict[str, Any]:
    row: dict[str, Any] = {"id": test.id}
    row.update(test.settings)
    predicted = result.threshold if result.status == SearchStatus.CONVERGED else math.nan
    row.update(
        measured=test.measured,
        predicted=predicted,
        error=predicted / test.measured - 1.0,
        role=problem.spec.role(test.id),
        lower=result.lower,
        upper=result.upper,
        lower_value=_number(result.lower_value),
        upper_value=_number(result.upper_value),
        steps=result.steps,
        status=result.status,
        message=result.message,
    )
    return row


def _number(value: Any) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


def _residual(problem, test, result, values) -> float:
    """predicted/measured − 1; a threshold outside the bracket counts as the bracket's end
    it lies beyond (the error is at least that); a failed search fails the fit."""
    if result.status == SearchStatus.CONVERGED:
        return result.threshold / test.measured - 1.0
    if result.status == SearchStatus.NOT_BRACKETED:
        spec = problem.search_spec(test, values)
        above = float(result.lower_value) - float(spec.target) > 0.0
        end = spec.low if above else spec.high
        return end / test.measured - 1.0
    raise FitFailed(f"test {test.id}: search {result.status}: {result.message}")


def run_calibration(config, *, comm, stop_event=None, fresh: bool = False) -> CalibrationResult:
    """Fit, predict and write (module docstring); raises :class:`Stopped` on a stop (the
    contact store keeps what was solved)."""
    start = time.perf_counter()
    spec = config.calibrate
    plan = make_plan(config)  # one combination (engine.run checks it before anything runs)
    problem = CalibrationProblem(config, plan.cases[0])
    output = Path(config.study.output)
    store = ContactStore(contact_dir(output))
    rank = comm.Get_rank()
    if fresh and rank == 0:
        shutil.rmtree(store.directory, ignore_errors=True)
        for path in (output, calibration_csv_path(config.study.summary_path)):
            path.unlink(missing_ok=True)
    comm.Barrier()
    store.load_index()
    context = CaseContext(OperatorCache(), config.study.checkpoint_dir)
    should_stop = None if stop_event is None else stop_event.is_set
    searches = TestSearches(problem, store, comm, context, should_stop)
    calibration = [test for test in spec.tests if test.id in spec.calibrate_on]
    log: list[dict[str, Any]] = []

    def residuals(values: dict[str, float]) -> np.ndarray:
        number = len(log)
        results = searches.run(calibration, values, number)
        found = np.array([_residual(problem, t, results[t.id], values) for t in calibration])
        entry: dict[str, Any] = {"evaluation": number, **values}
        entry.update({f"predicted_{t.id}": results[t.id].threshold for t in calibration})
        entry["sum_squares"] = float(np.sum(found**2))
        log.append(entry)
        if rank == 0:
            shown = ", ".join(f"{k} = {v:.6g}" for k, v in values.items())
            LOGGER.info(f"fit evaluation {number}: {shown}: Σ r² = {entry['sum_squares']:.4g}")
        return found

    fit = fit_values(
        residuals, spec.fit, spec.low, spec.high,
        rtol=spec.fit_rtol, max_evaluations=spec.max_evaluations,
    )  # fmt: skip
    results = searches.run(list(spec.tests), fit.values, len(log))
    rows = [_row(problem, test, results[test.id]) for test in spec.tests]
    outcome = CalibrationResult(rows, fit, log, searches.solves, time.perf_counter() - start)
    full = None  # rank 0: the results did not fit on the disk (every rank learns it)
    if rank == 0:
        try:
            write_calibration(config, outcome, store, problem.store_name)
        except OutputFull as error:
            full = (str(error.path), error.needed, error.free)
    full = comm.bcast(full, root=0)
    if full is not None:
        raise OutputFull(Path(full[0]), full[1], full[2])
    return outcome


def describe(outcome: CalibrationResult) -> str:
    """The closing lines: the fit and the errors of the predicted tests."""
    fit = outcome.fit
    values = ", ".join(f"{k} = {v:.6g}" for k, v in fit.values.items()) or "nothing fitted"
    errors = [abs(r["error"]) for r in outcome.rows if r["role"] == "predict"]
    errors = [e for e in errors if math.isfinite(e)]
    if fit.status == "predict-only":
        text = "nothing fitted: every test predicted"
    else:
        text = f"fit {fit.status}: {values} ({fit.evaluations} evaluations"
        text += f"; {fit.message})" if fit.message and fit.status != "converged" else ")"
    if errors:
        text += (
            f"\npredicted tests: median |error| {100 * float(np.median(errors)):.1f} %, "
            f"largest {100 * max(errors):.1f} % ({len(errors)} tests)"
        )
    for row in outcome.rows:  # the searches that make the run end as failed, and why
        if row["status"] != SearchStatus.CONVERGED:
            text += f"\ntest {row['id']} ({row['role']}): search {row['status']}"
            text += f": {row['message']}" if row["message"] else ""
    return text + f"\n{outcome.solves} contact solutions computed this run"


def calibrate(comm, config, run, options, stop_event):
    """The :class:`~engine.run.StudyRun` of a calibration (:func:`engine.run.run_study`):
    ``"completed"`` when every test's final search converged, ``"failed"`` otherwise (the
    fit's or a search's status says why), ``"interrupted"`` on a stop (rerun to resume),
    ``"planned"`` for a dry run."""
    rank = comm.Get_rank()
    spec = config.calibrate
    if options.dry_run:
        if rank == 0:
            LOGGER.info(
                f"calibration {config.study.name!r}: {len(spec.tests)} tests "
                f"({len(spec.calibrate_on)} calibrate, "
                f"{len(spec.tests) - len(spec.calibrate_on)} predict), fit "
                f"{', '.join(spec.fit) or 'nothing'}; {config.search.parameter} searched until "
                f"{config.search.column} reaches {config.search.target!r}"
            )
        return run
    try:
        outcome = run_calibration(config, comm=comm, stop_event=stop_event, fresh=options.fresh)
    except Stopped:
        message = "stopped: the contact solutions so far are kept; rerun to resume"
        if rank == 0:
            LOGGER.warning(message)
        return dataclasses.replace(run, status="interrupted", message=message)
    except OutputFull as full:  # on every rank alike; the command line prints the message
        return dataclasses.replace(run, status="output-full", message=str(full))
    if rank == 0:
        LOGGER.info(describe(outcome))
    converged = sum(row["status"] == SearchStatus.CONVERGED for row in outcome.rows)
    ok = converged == len(outcome.rows) and outcome.fit.status in FIT_OK
    return dataclasses.replace(
        run,
        status="completed" if ok else "failed",
        cases=len(outcome.rows),
        completed=converged,
        failed=len(outcome.rows) - converged,
        wall_time_s=outcome.wall_time_s,
        message=""
        if ok
        else f"fit {outcome.fit.status}; {converged}/{len(outcome.rows)} searches converged",
    )
