"""``equations.md`` and ``equations.tex`` of a model: the printed equations of its structure, with its values.

Everything the documents print of the derivation (coordinates, kinematics, partial velocities,
F*_r and F_r, and per constant its symbol, source, definition and unit) depends on the structure of
the model alone: :func:`flexkane.report.printed_structure` renders it with SymPy once per structure,
and :class:`flexkane.derivation_cache.Derivation` stores it beside the structure's equations. What
belongs to one model of that structure is filled in here, from plain data and without SymPy, so that
a changed value costs no rendering:

* the model's name, in the title;
* in the table of constants, the value of every constant (from the constants vector p) and the text
  given for a parameter that is an expression rather than a number.

:func:`flexkane.report.equations_markdown` and :func:`flexkane.report.equations_latex` assemble their
documents here too, so that both ways give the same bytes.
"""

from __future__ import annotations

import re

__all__ = ["PRINTED_KEYS", "constant_rows", "documents", "latex_document", "markdown_document",
           "number_text", "parameter_text", "tex_escape", "unit_tex"]

#: The keys of the printed equations of a structure (:func:`flexkane.report.printed_structure`):
#: the Markdown and LaTeX text between the title and the table of constants, the static columns
#: of that table, and where the chapter defines the modal constants it lists.
PRINTED_KEYS = ("md", "tex", "constants", "constants_source")

#: Lines of the LaTeX document before its title.
_LATEX_PREAMBLE = (r"\documentclass[10pt]{article}", r"\usepackage{amsmath}", r"\usepackage{longtable}",
                   r"\usepackage[margin=1.5cm,landscape]{geometry}", r"\allowdisplaybreaks", r"\begin{document}")


def tex_escape(text: str) -> str:
    """Plain text escaped for LaTeX (backslashes, underscores, percent and ampersand signs)."""
    return text.replace("\\", r"\textbackslash{}").replace("_", r"\_").replace("%", r"\%").replace("&", r"\&")


def unit_tex(unit: str) -> str:
    """A unit such as ``kg m^2`` or ``1/m^3`` in LaTeX text mode."""
    return re.sub(r"\^(-?\d+)", r"$^{\1}$", unit.replace(" ", r"\,"))


def number_text(value: float) -> str:
    """A constant's value as the table prints it (10 significant digits)."""
    return f"{value:.10g}"


def parameter_text(given) -> str:
    """The definition column of a parameter: the text it was given as, when not a number."""
    return "" if isinstance(given, (int, float)) else rf"\mathtt{{{tex_escape(str(given))}}}"


def constant_rows(columns, p, parameters) -> list[tuple[str, str, str, str, str]]:
    """The table of constants of one model from the static columns of its structure.

    Parameters
    ----------
    columns : list of sequence
        Per row, in the order printed: ``(index in p, name, kind, LaTeX symbol, source, definition,
        unit)`` (:func:`flexkane.report.constant_columns`); ``kind`` is ``"parameter"`` for a
        parameter of the model, whose definition is the text it is given as.
    p : sequence of float
        The constants vector of the model, in the order of the equations' constants [their units].
    parameters : mapping of str to number or str
        The model's parameters as given (``Model.parameters``).

    Returns
    -------
    list of (str, str, str, str, str)
        (LaTeX symbol, source, LaTeX definition, unit, value as text) per row.
    """
    rows = []
    for index, name, kind, symbol, source, definition, unit in columns:
        if kind == "parameter":
            definition = parameter_text(parameters[name])
        rows.append((symbol, source, definition, unit, number_text(p[index])))
    return rows


def markdown_document(name: str, body: str, rows=None, *, constants_source: str = "") -> str:
    """``equations.md``: the title with the model's ``name``, the printed equations ``body`` and, when
    ``rows`` are given (:func:`constant_rows`), the table of constants, introduced as defined at
    ``constants_source`` of the chapter (``"below eq. 8.22 and eq. 8.32"``)."""
    out = [f"# Equations of motion: {name}", body]
    if rows is not None:
        out += ["## Constants", "",
                f"Modal constants ({constants_source}; x along the beam from its root, "
                "$\\Phi_i$ of eq. 8.4 or the beam's family) and the values of the model:", "",
                "| symbol | of | definition | unit | value |", "|---|---|---|---|---|"]
        for sym, source, definition, unit, value in rows:
            d = f"${definition}$" if definition else ""
            out.append(f"| ${sym}$ | {source} | {d} | {unit} | {value} |")
        out.append("")
    return "\n".join(out)


def latex_document(name: str, body: str, rows=None) -> str:
    """``equations.tex``: the same content as :func:`markdown_document`, as a standalone LaTeX document."""
    doc = [*_LATEX_PREAMBLE, rf"\section*{{Equations of motion: {tex_escape(name)}}}", body]
    if rows is not None:
        doc += [r"\subsection*{Constants}", r"\begin{longtable}{lllll}",
                r"symbol & of & definition & unit & value \\ \hline \endhead"]
        for sym, source, definition, unit, value in rows:
            src = tex_escape(source.strip("`"))
            doc.append(f"${sym}$ & {src} & {'$' + definition + '$' if definition else ''} & "
                       f"{unit_tex(unit)} & {value} \\\\")
        doc.append(r"\end{longtable}")
    doc.append(r"\end{document}")
    return "\n".join(doc) + "\n"


def documents(printed: dict, name: str, p, parameters) -> dict[str, str]:
    """``equations.md`` and ``equations.tex`` of one model of a structure.

    Parameters
    ----------
    printed : dict
        The printed equations of the structure (:func:`flexkane.report.printed_structure`, or as stored).
    name : str
        The model's name.
    p : sequence of float
        The model's constants vector [their units].
    parameters : mapping of str to number or str
        The model's parameters as given.

    Returns
    -------
    dict
        ``{"md": text, "tex": text}``, equal to :func:`flexkane.report.equations_markdown` and
        :func:`flexkane.report.equations_latex` of the model with its constant values.
    """
    rows = constant_rows(printed["constants"], p, parameters)
    return {"md": markdown_document(name, printed["md"], rows, constants_source=printed["constants_source"]),
            "tex": latex_document(name, printed["tex"], rows)}
