"""The equations report: equations.md and equations.tex hold the chapter's steps, every F*_r and F_r,
and every constant with its definition and value; --pdf renders it or says why it cannot."""

import re
import shutil

import pytest

import flexkane
from flexkane import report
from flexkane.cli import main
from flexkane.report import (PDFLATEX_MISSING, _latex_lines, _latex_symbol, equations_latex,
                             equations_markdown, render_pdf)


@pytest.fixture(scope="module")
def chapter_two_modes():
    """The chapter's exact model with n = 2 (E_i, F_i, G_ij, H_ij with i != j appear)."""
    eom = flexkane.derive(flexkane.builtin_model("falling-beam-exact").with_modes(2))
    return eom, eom.constant_values()


def test_markdown_report_contains_every_inertia_and_active_force(chapter_two_modes):
    eom, values = chapter_two_modes
    text = equations_markdown(eom, values)
    for r in ("1", "2", "3", "4", "5"):
        assert f"F^*_{{u_{{{r}}}}} &=" in text
    assert r"(F_{u_{4}})_{\mathrm{elastic}} &= - H_{11} q_{4} - H_{12} q_{5}" in text    # eq. 8.31
    assert r"(F_{u_{2}})_{\mathrm{gravity}}" in text


def test_markdown_report_walks_kinematics_and_partial_velocities(chapter_two_modes):
    eom, values = chapter_two_modes
    text = equations_markdown(eom, values)
    for heading in ("## Generalized coordinates and speeds", "## Kinematics", "## Partial velocities",
                    "## Generalized inertia and active forces", "## Constants"):
        assert heading in text
    assert r"\dot q_{3} = u_{3}" in text                                         # eq. 8.14
    assert r"$(u_{1} - q_{4} u_{3} \Phi_{1}(x) - q_{5} u_{3} \Phi_{2}(x)" in text    # eq. 8.18
    assert r"beam B, $u_{4}$: $\partial v_P / \partial u_{4} = (0,\ \Phi_{1}(x))$" in text


def test_constants_table_gives_definitions_units_and_values(chapter_two_modes):
    eom, values = chapter_two_modes
    text = equations_markdown(eom, values)
    rows = {line.split("|")[1].strip(): line for line in text.splitlines() if line.startswith("| $")}
    assert r"\int_0^L \rho\,dx" in rows["$m_{B}$"] and "0.21991" in rows["$m_{B}$"]
    assert r"\int_0^L \rho\,x^2\,dx" in rows["$I_{B}$"] and "kg m^2" in rows["$I_{B}$"]
    assert r"\Phi_{1}(x)\,\Phi_{2}(x)" in rows["$G_{12}$"]
    assert "N/m" in rows["$H_{22}$"] and r"EI\,\Phi_{2}''" in rows["$H_{22}$"]
    assert "parameter" in rows["$Iz$"] and "mR*(c**2 + d**2)/12" in rows["$Iz$"]
    for s in eom.constants:                                 # every constant has a numeric value
        assert f"{values[s]:.10g}" in text


def test_latex_document_has_the_same_equations_and_balanced_delimiters(chapter_two_modes):
    eom, values = chapter_two_modes
    tex = equations_latex(eom, values)
    assert tex.startswith(r"\documentclass") and tex.rstrip().endswith(r"\end{document}")
    for r in range(1, 6):
        assert f"F^*_{{u_{{{r}}}}} &=" in tex
    assert tex.count(r"\begin{align*}") == tex.count(r"\end{align*}") == 6
    assert tex.count(r"\left") == tex.count(r"\right")
    assert r"kg\,m$^{2}$" in tex                             # units in text mode


def test_symbol_names_print_in_the_chapter_notation():
    assert _latex_symbol("u3'") == r"\dot{u}_{3}"
    assert _latex_symbol("Phi_1'''(0)") == r"\Phi_{1}'''(0)"
    assert _latex_symbol("Phi'_upper_2(L1)") == r"\Phi'_{upper,2}(L1)"
    assert _latex_symbol("G_arm_12") == r"G_{arm,12}"
    assert _latex_symbol("JPhi_11") == r"\mathrm{JPhi}_{11}"
    assert _latex_symbol("theta_pivot") == r"\theta_{pivot}"


def test_long_sums_break_into_lines_with_balanced_parentheses():
    eom = flexkane.derive(flexkane.builtin_model("flexible-arm"))
    names = report.latex_names(eom)
    for r in range(len(eom.all_speeds)):
        lines = _latex_lines(eom, report.collect_terms(eom, eom.F_r_star[r]), names)
        for line in lines:
            assert line.count(r"\left") == line.count(r"\right")
        assert max(len(line) for line in lines) < 600


def test_the_notebook_variant_prints_the_shear_and_moment_constants_of_eq_8_28():
    eom = flexkane.derive(flexkane.builtin_model("falling-beam"))
    text = equations_markdown(eom, eom.constant_values())
    assert r"\Phi_{1}'''(0)" in text and "-9.678017062" in text
    assert r"\int_0^L \Phi_{1}''''\,dx" in text


def test_pdf_without_pdflatex_is_a_message_not_an_error(tmp_path, monkeypatch):
    tex = tmp_path / "equations.tex"
    tex.write_text("\\documentclass{article}\\begin{document}x\\end{document}\n")
    monkeypatch.setattr(report.shutil, "which", lambda name: None)
    assert render_pdf(tex) == (None, PDFLATEX_MISSING)
    assert not (tmp_path / "equations.pdf").exists()


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="needs pdflatex")
def test_equations_tex_compiles_to_a_pdf(chapter_two_modes, tmp_path):
    eom, values = chapter_two_modes
    tex = tmp_path / "equations.tex"
    tex.write_text(equations_latex(eom, values))
    pdf, message = render_pdf(tex)
    assert message == "" and pdf.read_bytes().startswith(b"%PDF")


def test_run_writes_equations_md_and_tex_and_handles_pdf(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["run", "falling-beam-exact", "--out", str(out), "--quiet", "--t-end", "0.02", "--pdf"]) == 0
    md = (out / "equations.md").read_text()
    tex = (out / "equations.tex").read_text()
    assert len(re.findall(r"F\^\*_\{u_\{\d\}\} &=", md)) == 4 and len(re.findall(r"F\^\*_\{u_\{\d\}\} &=", tex)) == 4
    if shutil.which("pdflatex"):
        assert (out / "equations.pdf").read_bytes().startswith(b"%PDF")
    else:
        assert "pdflatex is not on PATH" in capsys.readouterr().err


def test_modal_constants_and_terms_print_in_natural_order():
    eom = flexkane.derive(flexkane.builtin_model("falling-beam-exact").with_modes(11))
    names = [s.name for s in eom.constants]
    e = [n for n in names if n.startswith("E_")]
    assert e == [f"E_{i}" for i in range(1, 12)]                  # not E_1, E_10, E_11, E_2, ...
    assert names.index("G_2_11") < names.index("G_9_10") < names.index("G_10_11")
    text = report.format_equations(eom)
    first = text.splitlines()[0]
    assert first.startswith("F*[u1] = u1'*")                        # terms in u' first, by speed
    assert " + ".join(f"E_{i}*q{i + 3}" for i in range(1, 12)) in first
    rows = [row[0] for row in report.constant_rows(eom)]
    assert rows.index("E_{2}") < rows.index("E_{10}") < rows.index("E_{11}")
    latex = report.format_equations(eom, latex=True)
    assert latex.index(r"E_{9} q_{12}") < latex.index(r"E_{10} q_{13}")


@pytest.mark.parametrize("name, modes", [("falling-beam-exact", 3), ("flexible-arm", None)])
def test_grouping_by_speed_derivatives_equals_sympy_collect(name, modes):
    import sympy as sp

    model = flexkane.builtin_model(name)
    eom = flexkane.derive(model.with_modes(modes) if modes else model)
    ud = list(eom.chain.ud.values())
    for expr in list(eom.F_r_star) + [e for forces in eom.F_r.values() for e in forces]:
        expanded = sp.expand(expr)
        assert report._collect_linear(expanded, ud) == sp.collect(expanded, ud)
    x = sp.Symbol("x")
    assert report._collect_linear(sp.expand(ud[0] ** 2 + x * ud[0]), ud) is None      # not linear in u'


def test_a_report_too_long_to_print_term_by_term_is_written_in_terms_of_intermediates(monkeypatch):
    """Above TERM_BY_TERM_MAX printed nodes the forces are printed through their common
    subexpressions, whose length grows with the distinct subexpressions only; below it the report
    is unchanged. Substituting the intermediates back gives the forces exactly."""
    import sympy as sp

    import flexkane
    from flexkane import report
    from flexkane.kane.equations import derive

    eom = derive(flexkane.builtin_model("flexible-arm"))
    flat = [e for r in range(len(eom.all_speeds))
            for e in (eom.F_r_star[r], *[v[r] for v in eom.F_r.values() if v[r] != 0])]
    size = report.printed_size(flat)
    assert size > len(flat)
    full = report.format_equations(eom)
    assert "x_0 =" not in full
    monkeypatch.setattr(report, "TERM_BY_TERM_MAX", size - 1)
    short = report.format_equations(eom)
    assert short.startswith("x_0 = ") and len(short) < len(full)
    intermediates, forces = report._forces(eom)
    values = {}
    for sym, expr in intermediates:
        values[sym] = expr.xreplace(values)
    assert sp.expand(forces[0][0].xreplace(values) - eom.F_r_star[0]) == 0
    md = report.equations_markdown(eom)
    assert "intermediates $x_k$" in md and "x_{0} &=" in md


def test_natural_order_sorts_a_name_before_the_same_name_with_digits():
    from flexkane.natural_order import natural_key

    names = ["m1", "E_10", "m", "E_2", "E_1_2", "E_1", "L", "L2", "q01", "q1"]
    assert sorted(names, key=natural_key) == ["E_1", "E_1_2", "E_2", "E_10", "L", "L2", "m", "m1", "q01", "q1"]
