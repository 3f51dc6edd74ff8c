"""``--dry-run`` of a sweep: the header gives the range of every swept parameter (not only the
first value) and the case table has a column per swept dotted key. Nothing is computed."""

from __future__ import annotations

from engine.cli import main
from engine.study.examples import study_toml

LOADS = [250.0, 500.0, 750.0, 1000.0, 1250.0]


def test_dry_run_of_a_load_and_mesh_sweep(tmp_path, capsys, monkeypatch):
    text = study_toml(
        "dry",
        "dry.h5",
        mesh={"n": None},
        loading={"kind": "cyclic", "load": None, "cycles": 1000},
        sweep={"mu1": [0.1, 0.4], "wear1": [1.33e-7], "loading.load": LOADS, "mesh.n": [16, 32]},
    )
    (tmp_path / "study.toml").write_text(text)
    monkeypatch.chdir(tmp_path)
    assert main(["study.toml", "--dry-run"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == (
        "study 'dry' (study.toml): 20 cases, cyclic, P = 250 … 1250 N (5 values), 1,000 cycles; "
        "swept: mu1 = 0.1, 0.4, mu2 = mu1; loading.load = 250 … 1250 N (5 values); "
        "mesh.n = 16, 32"
    )
    header = lines.index(next(line for line in lines if line.startswith("case_id")))
    columns = lines[header].split()
    assert columns[-4:] == ["loading.load", "mesh.n", "order", "action"]
    rows = [line.split() for line in lines[header + 1 :]]
    assert len(rows) == 20
    table = {row[0]: (float(row[6]), int(row[7])) for row in rows}
    assert table["mu0.4_w1.33e-07_b0_load1250_n32"] == (1250.0, 32)
    assert sorted({load for load, _ in table.values()}) == LOADS
    assert not (tmp_path / "dry.h5").exists()


def _first_line(tmp_path, capsys, monkeypatch, **sweep) -> str:
    text = study_toml(
        "follow", "follow.h5", loading={"kind": "cyclic", "cycles": 1000}, sweep=sweep
    )
    (tmp_path / "study.toml").write_text(text)
    monkeypatch.chdir(tmp_path)
    assert main(["study.toml", "--dry-run"]) == 0
    return capsys.readouterr().out.splitlines()[0]


def test_dry_run_lists_what_the_user_swept_and_names_the_followers(tmp_path, capsys, monkeypatch):
    """mu2 and wear2 left out follow mu1 and wear1: named beside them, not listed as swept;
    swept explicitly, they are listed; wear2 = "proportional" varies with mu2 alone."""
    line = _first_line(tmp_path, capsys, monkeypatch, mu1=[0.1, 0.4], wear1=[1e-7, 2e-7])
    assert line.endswith(
        "swept: mu1 = 0.1, 0.4, mu2 = mu1; wear1 = 1e-07, 2e-07 1/MPa, wear2 = wear1"
    )
    line = _first_line(
        tmp_path, capsys, monkeypatch, mu1=[0.1, 0.4], mu2=[0.1, 0.4], wear1=[1e-7], wear2=[1e-7]
    )
    assert line.endswith("swept: mu1 = 0.1, 0.4; mu2 = 0.1, 0.4")
    line = _first_line(
        tmp_path, capsys, monkeypatch, mu1=[0.1], mu2=[0.1, 0.4], wear1=[1e-7],
        wear2="proportional",
    )  # fmt: skip
    assert line.endswith("swept: mu2 = 0.1, 0.4; wear2 = wear1·mu2/mu1 = 1e-07, 4e-07 1/MPa")
