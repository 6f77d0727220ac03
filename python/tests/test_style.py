"""wisp.Style: the schema's fields by their TOML names, checked with the reader's messages."""
import pytest

import wisp


def test_fields_read_and_set_by_toml_names():
    style = wisp.Style.preset("ponytail")
    style.roots.strands = 20000
    style.solve.stiffness = 2.5
    assert style.roots.strands == 20000
    assert style.solve.stiffness == 2.5
    assert "strands = 20000" in style.to_toml()


def test_every_schema_field_reads():
    style = wisp.Style()
    for field in wisp.schema():
        if field["type"] == "groups":
            continue
        section, _, key = field["path"].rpartition(".")
        obj = style
        for part in filter(None, section.split(".")):
            obj = getattr(obj, part)
        getattr(obj, key)  # no exception: every field is reachable by its TOML name


def test_toml_round_trip():
    style = wisp.Style.preset("braid")
    style.color.hue = {"distribution": "normal", "mean": 30, "stddev": 5, "min": 0, "max": 360}
    assert style.color.hue["mean"] == 30
    again = wisp.Style.from_toml(style.to_toml())
    assert again.to_toml() == style.to_toml()


def test_from_toml_file(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("[roots]\nstrands = 1234\nwisps = 50\n")
    assert wisp.Style.from_toml(path).roots.strands == 1234
    assert wisp.Style.from_toml(str(path)).roots.wisps == 50


def test_out_of_range_names_field_and_range():
    style = wisp.Style()
    before = style.to_toml()
    with pytest.raises(ValueError, match=r"solve\.stiffness") as e:
        style.solve.stiffness = -1
    assert "-1" in str(e.value) or "range" in str(e.value) or "[" in str(e.value)
    assert style.to_toml() == before  # unchanged on error


def test_negative_count_is_value_error():
    with pytest.raises(ValueError, match=r"roots\.strands"):
        wisp.Style().roots.strands = -5


def test_nan_is_value_error():
    with pytest.raises(ValueError, match=r"solve\.stiffness"):
        wisp.Style().solve.stiffness = float("nan")


def test_wrong_type_is_value_error():
    with pytest.raises(ValueError, match=r"roots\.strands"):
        wisp.Style().roots.strands = "many"


def test_unknown_field_suggests():
    with pytest.raises(ValueError, match=r"did you mean 'roots\.strands'"):
        wisp.Style().roots.strand = 5


def test_wisp_error_is_value_error():
    assert issubclass(wisp.Error, ValueError)


def test_unknown_preset_lists_names():
    with pytest.raises(ValueError, match="ponytail"):
        wisp.Style.preset("no-such-style")


def test_missing_style_file():
    with pytest.raises(FileNotFoundError, match="nope.toml"):
        wisp.Style.from_toml("nope.toml")


def test_groups_read_and_replaced():
    style = wisp.Style.preset("ponytail")
    groups = style.groups
    assert groups and isinstance(groups[0], dict)
    style.groups = []
    assert style.groups == []
    style.groups = groups
    assert style.groups == groups


def test_bad_group_is_value_error():
    style = wisp.Style.preset("ponytail")
    with pytest.raises(ValueError, match="group"):
        style.groups = [{"no_such_key": 1}]


def test_preset_names():
    assert "default" in wisp.preset_names()


def test_the_stubs_type_every_style_field_as_the_schema_does():
    """python/wisp/__init__.pyi's style fields are what python/style_stubs.py makes from the
    schema (one source of truth), and a field's stub type is the type its value has."""
    import ast
    import os
    import pathlib
    import subprocess
    import sys

    source = pathlib.Path(os.environ.get("WISP_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
    check = subprocess.run([sys.executable, str(source / "python" / "style_stubs.py"), "--check"],
                           capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
    stubs = ast.parse((source / "python" / "wisp" / "__init__.pyi").read_text())
    classes = {n.name: n for n in stubs.body if isinstance(n, ast.ClassDef)}
    roots = {a.target.id: ast.unparse(a.annotation) for a in classes["_RootsSection"].body
             if isinstance(a, ast.AnnAssign)}
    assert roots["strands"] == "int"
    s = wisp.Style.preset("short")
    assert isinstance(s.roots.strands, int)
    growth = {a.target.id: ast.unparse(a.annotation) for a in classes["_GrowthSection"].body
              if isinstance(a, ast.AnnAssign)}
    assert growth["part"].startswith("Literal[") and repr(s.growth.part) in growth["part"]
