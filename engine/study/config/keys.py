"""What every key of a study file means: type, default, unit and meaning, as data.

The parser (:mod:`engine.study.config`) decides which keys exist and checks their values; this
table describes them for people. ``scripts/reference.py`` turns it into the study-file
reference of the manual (``docs/reference/study-file.md``), and ``tests/test_docs.py`` checks
it against the parser: every key the parser accepts is described here and nothing else, every
constant default is the one the parser resolves, and every sweepable key has the unit of
``SWEEPABLE``. A new key is one line here next to its line in the parser.

Units are those of the paper: mm, N, MPa, wear coefficients in 1/MPa, angles in degrees; "1"
is dimensionless and "–" marks a text or a list that has no unit.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["REQUIRED", "SECTIONS", "StudyKey", "STUDY_KEYS"]

REQUIRED = "required"


@dataclass(frozen=True)
class StudyKey:
    """One key of a study file as the manual describes it.

    Parameters
    ----------
    section : str
        The TOML table, e.g. ``"loading"``.
    name : str
        The key inside the table, e.g. ``"load"``.
    type : str
        The TOML type a value must have ("number", "integer", "text", "list of numbers" …).
    default : str
        The value used when the key is absent, as text, or :data:`REQUIRED`.
    unit : str
        The unit of the value ("1" dimensionless, "–" none).
    meaning : str
        What the key sets, in one or two sentences (Markdown).
    """

    section: str
    name: str
    type: str
    default: str
    unit: str
    meaning: str


#: Sections in the order of the reference; each with what it describes.
SECTIONS = {
    "study": "the study's name and where its results go",
    "material": "the two elastic bodies: half-space A and punch B",
    "punch": "the punch profile",
    "mesh": "the square grid of surface elements",
    "loading": "the loading kind and its signal",
    "wear": "the wear law (cyclic and fretting kinds)",
    "subsurface": "the x–z stress plane below the surface",
    "sweep": "the parameters that vary: every combination is a case",
    "search": "a threshold search along one parameter (optional)",
    "solver": "solver tolerances, iterations and FFTs",
    "testing": "fault injection for tests",
    "fatigue": "multiaxial fatigue criteria on the fretting cycles (optional; fretting only)",
}

_K = StudyKey
STUDY_KEYS = (
    _K("study", "name", "text", REQUIRED, "–", "name of the study, stored in the results file"),
    _K("study", "output", "text", REQUIRED, "–",
       "path of the results file (`.h5` or `.hdf5`), relative to the working directory of the "
       "command; the summary `.csv` is written beside it"),
    _K("study", "output_strategy", "text", '"auto"', "–",
       '`"single"`: rank 0 writes; `"mpio"`: every rank writes its cases through parallel '
       'HDF5; `"auto"`: mpio when h5py is MPI-enabled and there is more than one rank'),
    _K("material", "E_A", "number", REQUIRED, "MPa", "Young's modulus of the half-space"),
    _K("material", "nu_A", "number", REQUIRED, "1",
       "Poisson's ratio of the half-space, in (−1, 0.5)"),
    _K("material", "E_B", "number", REQUIRED, "MPa", "Young's modulus of the punch"),
    _K("material", "nu_B", "number", REQUIRED, "1", "Poisson's ratio of the punch, in (−1, 0.5)"),
    _K("punch", "shape", "text", '"flat"', "–",
       '`"flat"` (flat-ended cylinder, sharp edge), `"rounded"` (flat face with a toroidal '
       'edge), `"sphere"`; line contacts in plane strain: `"cylinder"` or `"pad"` (a flat '
       'pad with rounded edges)'),
    _K("punch", "radius", "number", REQUIRED, "mm",
       "flat: punch radius a0; rounded: radius of the flat face; sphere and cylinder: radius "
       "R; pad: half-width b of the flat"),
    _K("punch", "edge_radius", "number", 'required for `"rounded"` and `"pad"`', "mm",
       'edge radius of a rounded punch (0 is the sharp flat punch) or of a pad\'s rounds'),
    _K("mesh", "n", "integer", REQUIRED, "1", "elements per side of the square grid (≥ 8)"),
    _K("mesh", "half_width", "number",
       "flat: 1.05·radius; rounded: 1.05·(radius + edge_radius); sphere: 1.5 Hertz radii", "mm",
       "half-width of the square grid; a contact that reaches its border fails the case"),
    _K("mesh", "reference_distance", "number", "10", "mm",
       "line contacts: distance of the datum of the 2-D surface displacements (the size of the "
       "bodies; at least 2·half_width)"),
    _K("loading", "kind", "text", REQUIRED, "–",
       '`"static"` (one loading), `"cyclic"` (normal load cycles with wear, the paper\'s '
       'Section 7.2) or `"fretting"` (a held normal load and an oscillating tangential motion)'),
    _K("loading", "load", "number", REQUIRED, "N", "peak normal load P"),
    _K("loading", "steps", "integer", "10", "1",
       "load increments: static, of the loading; cyclic, per half cycle; fretting, per quarter "
       "tangential cycle and of the normal loading"),
    _K("loading", "cycles", "integer", "required (cyclic, fretting)", "1",
       "load cycles N to simulate, with cycle jumping"),
    _K("loading", "record", "list of integers", "[cycles]", "–",
       "cycles at which the surface fields and stresses are stored (0 = unworn)"),
    _K("loading", "max_wear_fraction", "number", "0.004", "1",
       "cycle-jump control: the largest wear per jump as a fraction of the peak elastic approach"),
    _K("loading", "amplitude", "number", "one of the two (fretting)", "mm",
       "rigid tangential displacement amplitude δ* (displacement control)"),
    _K("loading", "force_amplitude", "number", "one of the two (fretting)", "N",
       "tangential force amplitude Q* (force control); must be below μP"),
    _K("loading", "direction", "number", "0", "degree", "sliding direction, from x (fretting)"),
    _K("loading", "bulk_stress_max", "number", "0", "MPa",
       "line fretting: bulk stress along x in the flat at +Q* (or +δ*), in phase with the signal"),
    _K("loading", "bulk_stress_min", "number", "0", "MPa",
       "line fretting: bulk stress along x in the flat at −Q* (or −δ*)"),
    _K("wear", "law", "text", '"archard"', "–",
       '`"archard"`: Archard\'s orthotropic law (Eqs. 12–14), `[sweep] wear1, wear2` in 1/MPa; '
       '`"energy"`: depth increment = α × local frictional work, `[sweep] alpha` in mm³/J'),
    _K("wear", "pad_coefficient", "number", "none (the pad does not wear)", "1/MPa or mm^3/J",
       "the punch's (pad's) wear coefficient, in the unit of the flat's law: both bodies wear"),
    _K("subsurface", "depth", "number", "1.5", "punch radii",
       "depth of the stress plane, in punch radii (sphere: Hertz contact radii)"),
    _K("subsurface", "layers", "integer", "16", "1",
       "graded depth layers of the stress plane (≥ 2)"),
    _K("sweep", "mu1", "list of numbers", REQUIRED, "1", "friction coefficient along e1"),
    _K("sweep", "mu2", "list of numbers", "mu1", "1", "friction coefficient along e2"),
    _K("sweep", "wear1", "list of numbers", "required (cyclic, fretting); [0] static", "1/MPa",
       "Archard wear coefficient i1 along e1"),
    _K("sweep", "wear2", "list of numbers or text", "wear1", "1/MPa",
       'wear coefficient i2 along e2, or `"proportional"`: wear1·mu2/mu1 (Section 7.3)'),
    _K("sweep", "beta", "list of numbers", "[0]", "degree",
       "angle of the tribological axes e1, e2 from x"),
    _K("sweep", "alpha", "list of numbers", 'required with `law = "energy"`', "mm^3/J",
       "dissipated-energy wear coefficient, instead of wear1 and wear2"),
    _K("sweep", "zip", "list of lists of texts", "[]", "–",
       "groups of dotted keys that vary together (equal list lengths) instead of forming "
       "their product"),
    _K("search", "parameter", "text", REQUIRED, "–",
       "the dotted key searched, any continuous sweepable key (e.g. `loading.amplitude`); it "
       "must not be swept or set in its own section"),
    _K("search", "low", "number", REQUIRED, "the parameter's unit", "low end of the bracket"),
    _K("search", "high", "number", REQUIRED, "the parameter's unit", "high end of the bracket"),
    _K("search", "column", "text", REQUIRED, "–",
       "the summary column whose crossing is searched (e.g. `slip_regime` or `q_amplitude`)"),
    _K("search", "target", "number or text", REQUIRED, "the column's unit",
       "text column: the value on one side (e.g. `\"gross\"`); numeric: the level crossed"),
    _K("search", "rtol", "number", "0", "1",
       "relative tolerance on the threshold (rtol + atol > 0)"),
    _K("search", "atol", "number", "0", "the parameter's unit",
       "absolute tolerance on the threshold"),
    _K("search", "method", "text", 'bisection for a text column, illinois for a number', "–",
       '`"bisection"` or `"illinois"` (safeguarded regula falsi, numeric columns only)'),
    _K("search", "max_steps", "integer", "60", "1",
       "cases one search may take; beyond, it ends `not-converged`"),
    _K("solver", "tol", "number", "1e-8 static, 1e-6 cyclic and fretting", "1",
       "relative tolerance of each increment's contact solve (at most 1e-2)"),
    _K("solver", "maxiter", "integer", "20000", "1",
       "iterations per increment; a solve that reaches it fails the case"),
    _K("solver", "threads", "integer", "1", "1", "FFTW threads per rank"),
    _K("solver", "fft_planner", "text", '"estimate"', "–",
       '`"estimate"`: the same FFTW plans in every process, so runs and rank counts give '
       'bit-identical results; `"measure"`: timed plans, faster, may differ in the last digits'),
    _K("testing", "fail_cases", "list of texts", "[]", "–", "case ids that fail on purpose"),
    _K("fatigue", "criteria", "list of texts", REQUIRED, "–",
       '`"crossland"`, `"dang_van"`, `"swt"` (Smith–Watson–Topper), `"fatemi_socie"`; each '
       "needs its constants below, which have no defaults"),
    _K("fatigue", "sigma_d", "number", "required (crossland, dang_van)", "MPa",
       "fully reversed tension–compression fatigue limit"),
    _K("fatigue", "tau_d", "number", "required (crossland, dang_van)", "MPa",
       "fully reversed torsion fatigue limit"),
    _K("fatigue", "sigma_f", "number", "required (swt)", "MPa",
       "fatigue strength coefficient σ'_f (Basquin)"),
    _K("fatigue", "b", "number", "required (swt)", "1", "fatigue strength exponent (< 0)"),
    _K("fatigue", "eps_f", "number", "required (swt)", "1",
       "fatigue ductility coefficient ε'_f (Coffin–Manson)"),
    _K("fatigue", "c", "number", "required (swt)", "1", "fatigue ductility exponent (< 0)"),
    _K("fatigue", "tau_f", "number", "required (fatemi_socie)", "MPa",
       "shear fatigue strength coefficient τ'_f"),
    _K("fatigue", "gamma_f", "number", "required (fatemi_socie)", "1",
       "shear fatigue ductility coefficient γ'_f"),
    _K("fatigue", "b0", "number", "required (fatemi_socie)", "1",
       "shear fatigue strength exponent (< 0)"),
    _K("fatigue", "c0", "number", "required (fatemi_socie)", "1",
       "shear fatigue ductility exponent (< 0)"),
    _K("fatigue", "k", "number", "required (fatemi_socie)", "1",
       "normal-stress sensitivity of Fatemi–Socie"),
    _K("fatigue", "sigma_y", "number", "required (fatemi_socie)", "MPa", "yield strength"),
    _K("fatigue", "method", "text", '"hotspot"', "–",
       'critical distance: `"hotspot"` (the maximum over the plane), `"point"` (at depth ℓ/2 '
       'below the surface hot spot), `"line"` (mean over depth 0 … 2ℓ there), `"area"` (mean '
       "over the half-disc of radius 1.32 ℓ); evaluated at those exact points"),
    _K("fatigue", "length", "number", 'required unless `method = "hotspot"`', "mm",
       "the material's critical distance ℓ"),
    _K("fatigue", "amplitude_method", "text", '"chord"', "–",
       '√J2,a: `"chord"` (half the longest chord of the deviatoric path) or `"ball"` (radius of '
       "the minimum circumscribed ball)"),
    _K("fatigue", "plane_step", "number", "1", "degree",
       "resolution of the critical-plane search of swt and fatemi_socie (divides 180)"),
    _K("fatigue", "every_cycle", "boolean", "false", "–",
       "evaluate every simulated cycle too (hot spots in `history/`), not only the recorded "
       "cycles; one full evaluation per simulated cycle"),
)  # fmt: skip
