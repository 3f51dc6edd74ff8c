import pytest

from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.material import paper_material
from engine.solvers.contact import ContactSolver
from engine.solvers.friction import FrictionLaw

RADIUS = 1.8  # mm, a0 of Section 7
LOAD = 714.0  # N, Section 7.1


@pytest.fixture(scope="session")
def material():
    return paper_material()


@pytest.fixture(scope="session")
def frictionless_64(material):
    """64 x 64 elements over the square of half-width 1.05 a0 (the paper's mesh zone)."""
    grid = Grid.square(64, 1.05 * RADIUS)
    return ContactSolver(grid, material, FlatPunch(RADIUS), FrictionLaw(0.0, 0.0))


@pytest.fixture
def small_text(monkeypatch):
    """Texts below the figures' MIN_FONT_SIZE, per figure title: every figure closed by
    ``engine.analysis.figures`` is checked just before it is closed (after it was drawn for
    saving). A test draws its figures, then asserts the returned dict is empty."""
    import matplotlib.pyplot as plt
    from matplotlib.text import Text

    from engine.analysis import figures

    small: dict[str, set] = {}
    close = plt.close

    def checked_close(figure):
        texts = {
            (text.get_text(), text.get_fontsize())
            for text in figure.findobj(Text)
            if text.get_visible()
            and text.get_text()
            and text.get_fontsize() < figures.MIN_FONT_SIZE
        }
        if texts:
            small[figure.get_suptitle()] = texts
        close(figure)

    monkeypatch.setattr(figures.plt, "close", checked_close)
    return small


# ------------------------------------------------------------------ the validation table
class ValidationRecorder:
    """Writes a test's measured figure for the manual's validation table.

    ``scripts/validation.py`` runs the tests marked ``validation`` with the environment
    variable ``ENGINE_VALIDATION_RECORD`` naming a file; each call of :meth:`record` then
    appends one row (JSON) to it. Without the variable nothing is written. Record after the
    asserts, so that a row exists only when its check passed.
    """

    def __init__(self, path: str | None, test: str) -> None:
        self.path, self.test = path, test

    def record(self, check: str, tolerance: str, measured: str) -> None:
        """One row: what is compared, the tolerance and why, the measured figure (text)."""
        if not self.path:
            return
        import json

        row = {"test": self.test, "check": check, "tolerance": tolerance, "measured": measured}
        with open(self.path, "a", encoding="utf-8") as file:
            file.write(json.dumps(row, ensure_ascii=False) + "\n")


@pytest.fixture
def validation(request):
    """A :class:`ValidationRecorder` for this test (see scripts/validation.py)."""
    import os

    return ValidationRecorder(os.environ.get("ENGINE_VALIDATION_RECORD"), request.node.nodeid)
