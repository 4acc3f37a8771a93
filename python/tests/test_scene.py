"""Scenes from Python: constructors, overrides by dotted path, TOML round
trip, designations, and errors that name the field's path."""

from __future__ import annotations

import math

import pytest

import chaindrive as cd


def test_the_paper_drive_is_built_in():
    scene = cd.Scene.l60mc()
    d = scene.to_dict()
    assert scene.name == d["name"] == "MAN B&W L60MC camshaft chain (Pedersen 2005)"
    assert [s["teeth"] for s in d["sprockets"]] == [60, 30, 28, 30]
    assert d["chain"]["rollers"] == 122


def test_from_file_reads_a_scene(data):
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    assert scene.name == "16B-1 by designation, 19T/38T"
    # str paths as well as pathlib
    assert cd.Scene.from_file(str(data / "designation_16b.toml")) == scene


def test_to_toml_reads_back_as_the_same_scene():
    scene = cd.Scene.l60mc().with_({"chain.pretension_n": 18000.0})
    again = cd.Scene.from_toml(scene.to_toml())
    assert again == scene and again.to_dict() == scene.to_dict()
    assert again != cd.Scene.l60mc()
    assert again.to_dict()["chain"]["pretension_n"] == 18000.0


def test_with_sets_values_by_the_study_plans_paths():
    base = cd.Scene.l60mc()
    s = base.with_({"sprockets.0.speed_rpm": 60, "sprockets[2].mass_kg": 200.5})
    d = s.to_dict()
    assert d["sprockets"][0]["speed_rpm"] == 60.0
    assert d["sprockets"][2]["mass_kg"] == 200.5
    # keyword form, and the base is unchanged (scenes are immutable)
    k = base.with_(**{"chain.pretension_n": 15000})
    assert k.to_dict()["chain"]["pretension_n"] == 15000.0
    assert base.to_dict()["chain"]["pretension_n"] == 21000.0


def test_numpy_scalars_are_values():
    np = pytest.importorskip("numpy")
    s = cd.Scene.l60mc().with_({"sprockets.0.speed_rpm": np.float64(90.0), "chain.rollers": np.int64(122)})
    assert s.to_dict()["sprockets"][0]["speed_rpm"] == 90.0


def test_a_bad_value_raises_with_the_field_path():
    with pytest.raises(cd.SceneError) as e:
        cd.Scene.l60mc().with_({"sprockets.2.teeth": 2})
    assert e.value.path == "sprockets[2].teeth"
    assert str(e.value).startswith("sprockets[2].teeth: must lie in 5..=300, got 2")
    assert isinstance(e.value, ValueError)


def test_an_unknown_path_names_the_path_and_what_exists():
    with pytest.raises(cd.SceneError) as e:
        cd.Scene.l60mc().with_({"chain.colour": 3})
    assert e.value.path == "chain.colour"
    assert "no such field" in str(e.value) and "pretension_n" in str(e.value)
    with pytest.raises(cd.SceneError) as e:
        cd.Scene.l60mc().with_({"sprockets.7.teeth": 20})
    assert e.value.path == "sprockets[7]"
    assert "allowed indices: 0 to 3" in str(e.value)


def test_a_value_of_the_wrong_type_names_the_type():
    with pytest.raises(cd.SceneError) as e:
        cd.Scene.l60mc().with_({"chain.pretension_n": "high"})
    assert e.value.path == "chain.pretension_n"
    assert "allowed: a number" in str(e.value)


def test_every_problem_of_a_file_is_reported_with_file_line_and_column(tmp_path):
    text = cd.Scene.l60mc().to_toml()
    bad = text.replace("rollers = 122", "rollers = -3").replace("teeth = 28", "teeth = 2")
    assert bad != text
    path = tmp_path / "bad.toml"
    path.write_text(bad)
    with pytest.raises(cd.SceneError) as e:
        cd.Scene.from_file(path)
    lines = str(e.value).splitlines()
    assert set(e.value.paths) == {"chain.rollers", "sprockets[2].teeth"}
    # The command line's form: file:line:column: path: message
    rollers_line = bad.splitlines().index("rollers = -3") + 1
    assert f"{path}:{rollers_line}:11: chain.rollers: must be at least 4, got -3" in lines
    problem = next(p for p in e.value.problems if p["path"] == "chain.rollers")
    assert (problem["line"], problem["column"]) == (rollers_line, 11)


def test_toml_syntax_errors_raise_scene_error():
    with pytest.raises(cd.SceneError) as e:
        cd.Scene.from_toml("name = ")
    assert e.value.path == ""


def test_a_missing_file_is_an_os_error(tmp_path):
    with pytest.raises(OSError, match="cannot read scene"):
        cd.Scene.from_file(tmp_path / "none.toml")


def test_chains_lists_designations_with_sources():
    rows = cd.chains()
    names = [r["designation"] for r in rows]
    assert "ISO 606 16B-1" in names and "ANSI 80" in names
    (b16,) = cd.chains("16B")
    assert b16["pitch_m"] == pytest.approx(0.0254)
    assert b16["roller_mass_kg"] == pytest.approx(b16["mass_per_m_kg"] * b16["pitch_m"])
    assert b16["sources"]["dimensions"]
    with pytest.raises(ValueError, match="nearest"):
        cd.chains("ANSI 8O")


def test_a_multi_strand_chain_is_n_single_strands():
    """ASME B29.1's minimum tensile strength of an n-strand chain is n times
    the single strand's: ANSI 80-2 at 25,000 lbf (2 x 12,500 lbf)."""
    (single,) = cd.chains("ANSI 80")
    (double,) = cd.chains("ANSI 80-2")
    assert double["designation"] == "ANSI 80-2" and double["strands"] == 2
    assert double["tensile_strength_n"] == pytest.approx(25_000 * 4.4482216, rel=1e-3)
    assert double["tensile_strength_n"] == pytest.approx(2 * single["tensile_strength_n"])
    assert double["pitch_m"] == single["pitch_m"]
    assert "n x the single strand" in double["sources"]["strength"]
    with pytest.raises(ValueError, match="motorcycle"):
        cd.chains("520-2")


def test_with_designation_takes_the_tables_values(data):
    # ISO 606 16B and ANSI 80 share the 25.4 mm pitch: the same layout fits.
    scene = cd.Scene.from_file(data / "designation_16b.toml").with_designation("ANSI 80")
    chain = scene.to_dict()["chain"]
    assert chain["designation"] == "ANSI 80"
    assert "pitch_m" not in chain and "roller_mass_kg" not in chain
    with pytest.raises(cd.SceneError) as e:
        scene.with_designation("ANSI 999")
    assert e.value.path == "chain.designation"


def test_scene_warnings_are_sentences():
    w = cd.Scene.l60mc().with_({"solver.dt_s": 1e-3}).warnings()
    assert w and all(isinstance(s, str) for s in w)
    assert any("stability" in s for s in w)
