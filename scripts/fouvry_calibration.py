"""The Fouvry cylinder/plane crack-nucleation thresholds (ICF13, 2013) calibrated and
predicted by four models, into the manual.

Runs, with ``mpiexec -n RANKS python -m engine`` (a run resumes from its kept contact
solutions when its results exist), the bundled ``studies/fouvry_crack_nucleation.toml`` and
its variants, each calibrated on the 8 plain-fretting tests and predicting the 8
fretting-fatigue tests:

- ``crossland-point``: the bundled study (Crossland at ℓ by the point method; ℓ, σ_d and τ_d
  fitted: the source's fatigue limits could not be read);
- ``crossland-line``: the same, line method (the mean over 2ℓ below the hot spot);
- ``swt-point``, ``swt-line``: the SWT parameter (MPa) at ℓ reaching its value at the fatigue
  limit, ℓ and that value (``search.target``, σ_d²/E for fully reversed tension) fitted. SWT's
  life constants, which the study file requires, do not enter the SWT parameter.

and writes the block ``fouvry-calibration`` of docs/how-to/calibration.md (date, machine,
load, the command): per model the fitted values, the fit's status, its evaluations and the
contact solutions it kept; per test the measured threshold beside each model's prediction
and error (a threshold outside the search's bracket as a bound); the median and largest
|error| of the predicted tests whose search converged, whatever they are. The figure of the
bundled model goes to docs/figures/fouvry_calibration.png. (The time of the bundled study:
``benchmarks/bench_calibration.py``.)

    python scripts/fouvry_calibration.py                       # 2 ranks, all four models
    python scripts/fouvry_calibration.py --models crossland-point
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import time
import tomllib
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
STUDY = REPO / "studies" / "fouvry_crack_nucleation.toml"
DOCS = REPO / "docs" / "how-to" / "calibration.md"
FIGURE = REPO / "docs" / "figures" / "fouvry_calibration.png"
SWT = {  # the SWT parameter at ℓ; the life constants the parser requires are not used by it
    "fatigue": {"criteria": ["swt"], "sigma_d": None, "tau_d": None, "sigma_f": 1000.0,
                "b": -0.09, "eps_f": 0.6, "c": -0.6},
    "search": {"column": "swt_critical", "target": 1.0},
    "calibrate": {"fit": ["fatigue.length", "search.target"], "low": [0.002, 0.05],
                  "high": [0.2, 5.0]},
}  # fmt: skip
MODELS = {
    "crossland-point": {},
    "crossland-line": {"fatigue": {"method": "line"}},
    "swt-point": SWT,
    "swt-line": {**SWT, "fatigue": {**SWT["fatigue"], "method": "line"}},
}


def variant(name: str, directory: Path) -> Path:
    """The study file of model ``name`` in ``directory`` (the bundled one for the first)."""
    from engine.study.config.toml_writer import dump_toml

    data = tomllib.loads(STUDY.read_text())
    for section, changes in MODELS[name].items():
        for key, value in changes.items():
            if value is None:
                data[section].pop(key, None)
            else:
                data[section][key] = value
    data["study"]["name"] = f"fouvry_{name.replace('-', '_')}"
    data["study"]["output"] = str(REPO / "results" / f"fouvry_{name.replace('-', '_')}.h5")
    data["calibrate"]["tests"] = str(STUDY.with_name(data["calibrate"]["tests"]))
    path = directory / f"fouvry_{name.replace('-', '_')}.toml"
    path.write_text(dump_toml(data))
    return path


def run(study: Path, ranks: int, fresh: bool) -> tuple[float, str]:
    """(wall time s, stdout) of the study on ``ranks`` ranks (resumed when its kept contact
    solutions exist, unless ``fresh``)."""
    mpiexec = str(REPO / ".venv" / "bin" / "mpiexec")
    options = ["--no-progress-bar", *(["--fresh"] if fresh else [])]
    command = [mpiexec, "-n", str(ranks), sys.executable, "-m", "engine", str(study), *options]
    start = time.perf_counter()
    result = subprocess.run(command, cwd=REPO, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if result.returncode not in (0, 1):  # 1: a fit or a search did not converge (reported)
        raise SystemExit(f"{study.name}: exit {result.returncode}\n{result.stderr}")
    return wall, result.stdout


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--models", nargs="+", default=list(MODELS), choices=list(MODELS))
    parser.add_argument("--fresh", action="store_true", help="start every run over")
    parser.add_argument("--no-docs", action="store_true", help="print, do not write the docs")
    args = parser.parse_args()
    sys.path.insert(0, str(REPO))
    import h5py

    import engine
    from engine.analysis.calibration_report import draw_calibration, error_summary

    load = os.getloadavg()[0]
    directory = REPO / "results" / "fouvry_models"
    directory.mkdir(parents=True, exist_ok=True)
    frames, runs = {}, {}
    for name in args.models:
        study = variant(name, directory)
        wall, out = run(study, args.ranks, args.fresh)
        output = REPO / "results" / f"fouvry_{name.replace('-', '_')}.h5"
        frames[name] = engine.load_calibration(output)
        with h5py.File(output, "r") as file:
            runs[name] = (wall, len(file["calibration/contact/x"]))
        median, largest, count = error_summary(frames[name])
        print(f"{name}: {frames[name].attrs['fitted']} ({frames[name].attrs['fit_status']}), "
              f"predicted median |error| {100 * median:.1f} %, largest {100 * largest:.1f} %, "
              f"{wall:.0f} s", flush=True)  # fmt: skip
    text = block(frames, runs, load, args)
    print(text)
    if not args.no_docs:
        from engine.analysis.markdown import replace_block

        replace_block(DOCS, "fouvry-calibration", text)
        if "crossland-point" in frames:
            figure = draw_calibration(REPO / "results" / "fouvry_crossland_point.h5")
            figure.savefig(FIGURE, dpi=110)


def block(frames, runs, load: float, args) -> str:
    from engine.analysis.calibration_report import error_summary, outside
    from engine.analysis.markdown import markdown_table, measured_on

    note = (
        f"load average {load:.1f} at the start; `python scripts/fouvry_calibration.py "
        f"--ranks {args.ranks}`"
    )
    fits = []
    for name, frame in frames.items():
        _, solved = runs[name]
        units = frame.attrs["fitted_units"]
        values = ", ".join(
            f"{key.split('.')[-1]} = {value:.4g} {units.get(key, '')}".rstrip()
            for key, value in frame.attrs["fitted"].items()
        )
        median, largest, count = error_summary(frame)
        fits.append((name, values, frame.attrs["fit_status"], frame.attrs["fit_evaluations"],
                     solved, f"{count} of {len(frame[frame.role == 'predict'])}",
                     _percent(median), _percent(largest)))  # fmt: skip
    header = ("model", "fitted", "fit", "evaluations", "contact solutions",
              "predicted tests converged", "their median abs. error", "largest")  # fmt: skip
    first = next(iter(frames.values()))
    rows = []
    bounds = {name: {t: (s, e) for t, s, e in outside(frame)} for name, frame in frames.items()}
    for index, test in enumerate(first["id"]):
        measured = first["measured"][index]
        row = [test, first["role"][index], f"{measured:g}"]
        for name, frame in frames.items():
            predicted, error = frame["predicted"][index], frame["error"][index]
            if test in bounds[name]:
                side, end = bounds[name][test]
                row.append(f"{side} {end:.0f} ({side} {100 * (end / measured - 1):+.0f} %)")
            elif math.isnan(predicted):
                row.append(f"– ({frame['status'][index]})")
            else:
                row.append(f"{predicted:.0f} ({100 * error:+.0f} %)")
        rows.append(row)
    tests = ("test", "role", "measured Q*_CN (N/mm)", *(f"{name}: predicted" for name in frames))
    return (
        measured_on(note) + "\n\n" + markdown_table(header, fits) + "\n\n"
        + markdown_table(tests, rows)
    )  # fmt: skip


def _percent(value: float) -> str:
    return "–" if math.isnan(value) else f"{100 * value:.1f} %"


if __name__ == "__main__":
    main()
