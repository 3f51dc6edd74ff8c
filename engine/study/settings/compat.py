"""Compatibility with results files of earlier versions: the defaults they left out and the
placeholders they stored, so that such files resume (``same_fingerprint``) and are recognised
(``engine.output.identity``)."""

from __future__ import annotations

import json
from typing import Any

# Settings that results files written before every default was resolved left out
# when they held the solver's default then: such a file ran with exactly these values (they
# are history, not today's defaults).
FORMER_DEFAULTS = {("solver", "maxiter"): 20000, ("loading", "max_wear_fraction"): 0.004}


# What results files of static studies stored for the cyclic keys before they were left out
# (a stored static study then did not parse back: the parser refuses cycles in static loading).
STATIC_PLACEHOLDERS = {"cycles": 0, "record": []}


def fill_former_defaults(stored: dict[str, Any], current: dict[str, Any]) -> None:
    """Give a stored resolved study (or fingerprint data) the former defaults it left out,
    and take out the static placeholders it held (``STATIC_PLACEHOLDERS``), in place, where
    ``current`` does the same: results files of earlier versions resume."""
    for (section, key), value in FORMER_DEFAULTS.items():
        table = stored.get(section)
        if isinstance(table, dict) and key not in table and key in current.get(section, {}):
            table[key] = value
    loading, now = stored.get("loading"), current.get("loading", {})
    if isinstance(loading, dict) and loading.get("kind") == "static":
        for key, value in STATIC_PLACEHOLDERS.items():
            if key in loading and loading[key] == value and key not in now:
                del loading[key]


def same_fingerprint(stored: str | None, current: str) -> bool:
    """Whether a results file's ``stored`` fingerprint is the study's ``current`` one, the
    former defaults filled in (``fill_former_defaults``)."""
    if stored == current:
        return True
    try:
        old, new = json.loads(stored), json.loads(current)
    except (TypeError, ValueError):
        return False
    fill_former_defaults(old, new)
    return json.dumps(old, sort_keys=True) == json.dumps(new, sort_keys=True)
