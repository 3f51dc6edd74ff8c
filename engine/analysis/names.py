"""What figures and reports call a swept key: its name in the study-file schema and its unit
("displacement amplitude δ* (mm)" for ``loading.amplitude``), never the dotted key, which
belongs in the study file. Light: no pandas, no matplotlib (the reports import it)."""

from __future__ import annotations

from engine.output.summary import column_unit
from engine.study.config.keys import STUDY_KEYS

__all__ = ["key_title", "key_label", "value_text"]


def key_title(key: str) -> str:
    """What a swept key is called on figures and in reports: its ``title`` in the study-file
    schema (engine.study.config.keys; "displacement amplitude δ*" for ``loading.amplitude``),
    never the dotted key itself."""
    section, _, name = key.rpartition(".")
    section = section or "sweep"
    for study_key in STUDY_KEYS:
        if (study_key.section, study_key.name) == (section, name):
            return study_key.title
    return name.replace("_", " ")


def key_label(key: str, line: bool = False) -> str:
    """``title (unit)`` of a swept key for an axis (``line``: a line contact's units)."""
    unit = column_unit(key, line).replace("^3", "³").replace("^2", "²")
    unit = "°" if unit == "degree" else unit
    title = key_title(key)
    return f"{title} ({unit})" if unit and unit != "1" else title


def value_text(value, form: str = "g") -> str:
    """A swept value in figures and reports: a number in ``form``, a text (a swept
    ``surface.path``, ``surface.detrend`` …) as it is."""
    return value if isinstance(value, str) else format(value, form)
