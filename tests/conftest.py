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
