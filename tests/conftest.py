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
    """Texts below the figures' MIN_FONT_SIZE, and texts cut by the figure's edge, per figure
    title: every figure closed by ``engine.analysis.figures`` is checked just before it is
    closed (after it was drawn for saving). A test draws its figures, then asserts the
    returned dict is empty."""
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
        cut = _texts_cut_by_the_edge(figure, Text)
        if cut:
            small[figure.get_suptitle() + " (cut by the figure's edge)"] = cut
        close(figure)

    monkeypatch.setattr(figures.plt, "close", checked_close)
    return small


def _texts_cut_by_the_edge(figure, text_type) -> set[str]:
    """Texts that reach beyond the figure (a title or legend wider than the figure is cut
    off in the saved PNG): the figure's tight box (what is drawn) must lie inside it, to a
    hundredth of an inch; the texts beyond are named."""
    renderer = figure.canvas.get_renderer()
    tight, edge = figure.get_tightbbox(renderer), figure.bbox_inches
    slack = 0.01  # in
    if (
        tight.x0 >= edge.x0 - slack
        and tight.y0 >= edge.y0 - slack
        and tight.x1 <= edge.x1 + slack
        and tight.y1 <= edge.y1 + slack
    ):
        return set()
    cut = set()
    for text in figure.findobj(text_type):
        if text.get_visible() and text.get_text():
            box = text.get_window_extent(renderer).transformed(figure.dpi_scale_trans.inverted())
            if box.x0 < edge.x0 - slack or box.x1 > edge.x1 + slack or box.y1 > edge.y1 + slack:
                cut.add(text.get_text())
    return cut or {"(an artist beyond the figure's edge)"}


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
