"""equations.md and equations.tex: rendered once per structure, completed per model without SymPy.

A value change (``--set``, ``Model.with_values``) must cost no rendering of the equations (issue 25
item 1): the printed equations of a structure are stored beside it and only the model's name and its
table of constants are filled in. The oracle of the bytes is a fresh render of the changed model
(:func:`flexkane.report.equations_markdown`), derived afresh without the cache.
"""

from __future__ import annotations

import pytest

import flexkane
import flexkane.report
from flexkane.derivation_cache import Derivation
from flexkane.equations_document import constant_rows, documents


def count_calls(monkeypatch, *names) -> list:
    """Record the calls of the functions ``names`` of :mod:`flexkane.report` (by name)."""
    calls = []
    for name in names:
        def call(*args, _function=getattr(flexkane.report, name), **kwargs):
            calls.append(_function.__name__)
            return _function(*args, **kwargs)

        monkeypatch.setattr(flexkane.report, name, call)
    return calls


@pytest.fixture
def count_renders(monkeypatch):
    """Counts the renderings of printed equations with SymPy (every document goes through
    ``flexkane.report._printed_parts``)."""
    return count_calls(monkeypatch, "_printed_parts")


def fresh_render(model) -> dict:
    """The documents of ``model`` rendered from equations derived afresh (no cache)."""
    eom = flexkane.derive(model, cache=False)
    values = eom.constant_values(model)
    return {"md": flexkane.report.equations_markdown(eom, values), "tex": flexkane.report.equations_latex(eom, values)}


def test_value_change_does_not_render_the_equations_again(tmp_path, count_renders):
    base = flexkane.builtin_model("falling-beam")
    Derivation(base, tmp_path).equations(base, remember=True)
    assert len(count_renders) == 1
    changed = base.with_values({"EI": 40, "mR": 1.5, "u3": 2})
    Derivation(changed, tmp_path).equations(changed)           # another process would start the same way
    assert len(count_renders) == 1


def test_documents_of_a_value_change_are_those_of_a_fresh_render(tmp_path, count_renders):
    base = flexkane.builtin_model("falling-beam")
    Derivation(base, tmp_path).equations(base)
    changed = base.with_values({"EI": 40, "Iz": "mR*(c**2 + d**2)/10", "u3": 2})
    changed.name = "stiff_beam"
    documents_of_changed = Derivation(changed, tmp_path).equations(changed)
    expected = fresh_render(changed)
    assert documents_of_changed["md"].encode() == expected["md"].encode()
    assert documents_of_changed["tex"].encode() == expected["tex"].encode()


def test_constants_table_shows_the_new_value_and_the_title_the_new_name(tmp_path):
    base = flexkane.builtin_model("falling-beam")
    Derivation(base, tmp_path).equations(base)
    changed = base.with_values({"EI": 41.25, "Iz": "mR/7"})
    changed.name = "stiff_beam"
    md, tex = Derivation(changed, tmp_path).equations(changed).values()
    assert md.startswith("# Equations of motion: stiff_beam\n")
    assert r"\section*{Equations of motion: stiff\_beam}" in tex
    assert "| $EI$ | parameter |  |  | 41.25 |" in md
    assert r"| $Iz$ | parameter | $\mathtt{mR/7}$ |  | 0.1428571429 |" in md
    assert r"$EI$ & parameter &  &  & 41.25 \\" in tex
    assert "35.3" not in md.split("## Constants")[1]


def test_printed_equations_are_stored_once_per_structure_and_reused_across_values(tmp_path, count_renders):
    base = flexkane.builtin_model("falling-beam")
    Derivation(base, tmp_path).equations(base)
    stored = list((tmp_path / "derived").glob("*.equations.json"))
    assert len(stored) == 1
    before = stored[0].read_bytes()
    for ei in (20, 30, 50):
        changed = base.with_values({"EI": ei})
        md = Derivation(changed, tmp_path).equations(changed)["md"]
        assert f"| $EI$ | parameter |  |  | {ei} |" in md
    assert list((tmp_path / "derived").glob("*.equations.json")) == stored
    assert stored[0].read_bytes() == before and len(count_renders) == 1


def test_a_new_structure_renders_its_own_equations(tmp_path, count_renders):
    base = flexkane.builtin_model("falling-beam-exact")
    Derivation(base, tmp_path).equations(base)
    other = base.with_modes(2)
    md = Derivation(other, tmp_path).equations(other)["md"]
    assert len(count_renders) == 2
    assert md == fresh_render(other)["md"]


def test_damaged_printed_equations_are_rendered_again(tmp_path, count_renders):
    base = flexkane.builtin_model("falling-beam")
    expected = Derivation(base, tmp_path).equations(base)
    (stored,) = (tmp_path / "derived").glob("*.equations.json")
    stored.write_text('{"format": 1, "md": 3}', encoding="utf-8")
    assert Derivation(base, tmp_path).equations(base) == expected
    assert len(count_renders) == 2


def test_constant_rows_take_the_values_from_p_in_the_order_of_the_constants():
    columns = [[1, "E_1", "modal", "E_{1}", "beam B", r"\int_0^L \rho\,\Phi_{1}(x)\,dx", "kg"],
               [0, "EI", "parameter", "EI", "parameter", "", ""],
               [2, "Iz", "parameter", "Iz", "parameter", "", ""]]
    rows = constant_rows(columns, [35.3, 0.125, 1 / 3], {"EI": 35.3, "Iz": "mR_1/3"})
    assert rows == [("E_{1}", "beam B", r"\int_0^L \rho\,\Phi_{1}(x)\,dx", "kg", "0.125"),
                    ("EI", "parameter", "", "", "35.3"),
                    ("Iz", "parameter", r"\mathtt{mR\_1/3}", "", "0.3333333333")]


def test_documents_without_sympy_equal_the_report_of_a_controlled_model():
    model = flexkane.builtin_model("flexible-arm-pid").with_values({"Kp": "2*6"})
    eom = flexkane.derive(model)
    p = [float(v) for v in eom.parameter_vector(model)]
    assert documents(flexkane.report.printed_structure(eom), model.name, p, model.parameters) == \
        {"md": flexkane.report.equations_markdown(eom, eom.constant_values(model)),
         "tex": flexkane.report.equations_latex(eom, eom.constant_values(model))}


@pytest.mark.parametrize("form", [[], ["--latex"], ["--markdown"]])
def test_derive_prints_the_text_of_its_structure_rendered_once(tmp_path, monkeypatch, capsys, form):
    """``flexkane derive --set`` of a structure printed before renders nothing and prints what a fresh
    render of the changed model gives."""
    from flexkane.cli import main

    monkeypatch.setenv("FLEXKANE_CACHE_DIR", str(tmp_path))
    renders = count_calls(monkeypatch, "format_equations", "_printed_parts")
    assert main(["derive", "falling-beam", *form]) == 0
    assert len(renders) == 1
    capsys.readouterr()
    assert main(["derive", "falling-beam", "--set", "EI=40", *form]) == 0
    assert len(renders) == 1
    changed = flexkane.builtin_model("falling-beam").with_values({"EI": 40})
    eom = flexkane.derive(changed, cache=False)
    if form == ["--markdown"]:
        expected = flexkane.report.equations_markdown(eom, eom.constant_values(changed))
    else:
        expected = flexkane.report.format_equations(eom, latex=bool(form))
    assert capsys.readouterr().out == expected + "\n"


def test_runs_and_sweeps_of_the_library_never_reach_the_rendering():
    """Only the command line's ``run`` and ``derive`` (through :class:`Derivation`) write the printed
    equations: simulating, the results, the numbers of a run and the sweeps (whose variants are value
    changes) import no report, so no variant renders the equations."""
    from test_import_layers import MODULES, imported_modules

    readers = [m for m in MODULES if m.startswith(("flexkane.sweep", "flexkane.simulation", "flexkane.results",
                                                   "flexkane.run_manifest", "flexkane.model"))]
    assert "flexkane.sweep.worker" in readers and "flexkane.simulation" in readers
    offenders = [f"{module}:{line}" for module in readers for target, line in imported_modules(module, MODULES[module])
                 if target == "flexkane.report"]
    assert not offenders, offenders
