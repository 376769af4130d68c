"""The About panel: a mission's and a method's help, key equations as MathML (Chromium renders
MathML natively; viser's markdown has no LaTeX), the source paper and the published numbers.

LaTeX is converted with `latex2mathml` (optional dependency): without it the equations are
shown as LaTeX source with a note saying how to get them rendered.
"""

from __future__ import annotations

import html
from collections.abc import Sequence

from markdown_it import MarkdownIt

from solvers.mission import Mission

try:
    from latex2mathml.converter import convert as _latex2mathml
except ImportError:  # pragma: no cover - depends on the environment
    _latex2mathml = None

_MD = MarkdownIt("commonmark").enable("table")
MISSING = ("<p><em>Equations shown as LaTeX: install <code>latex2mathml</code> "
           "(pip install latex2mathml) to have them rendered.</em></p>")
STYLE = """<style>
.about {font-size: 0.85em; line-height: 1.4; padding: 0 12px 8px 12px;}
.about h3 {margin: 0.2em 0 0.3em 0; font-size: 1.15em;}
.about h4 {margin: 0.9em 0 0.2em 0; font-size: 1.0em;}
.about table {border-collapse: collapse; margin: 0.3em 0;}
.about td, .about th {border: 1px solid rgba(128,128,128,0.4); padding: 2px 6px;}
.about .eq {margin: 0.35em 0 0.6em 0; overflow-x: auto;}
.about .caption {opacity: 0.75; font-size: 0.92em;}
.about math {font-size: 1.12em;}
.about pre {white-space: pre-wrap;}
</style>"""


def mathml(latex: str) -> str:
    """Block MathML of a LaTeX formula (or the escaped source if no converter)."""
    if _latex2mathml is None:
        return f"<pre>{html.escape(latex)}</pre>"
    try:
        return _latex2mathml(latex, display="block")
    except Exception:  # noqa: BLE001 - a formula the converter cannot parse stays readable
        return f"<pre>{html.escape(latex)}</pre>"


def equations_html(equations: Sequence[tuple[str, str]]) -> str:
    parts = []
    for caption, latex in equations:
        parts.append(f'<div class="eq"><div class="caption">{html.escape(caption)}</div>'
                     f"{mathml(latex)}</div>")
    return "".join(parts)


def about_html(mission: Mission, method_key: str) -> str:
    """The whole About panel for one mission and its chosen method, as HTML."""
    method = mission.method(method_key)
    equations = [*mission.equations, *method.equations]
    out = [STYLE, '<div class="about">', f"<h3>{html.escape(mission.title)}</h3>",
           f"<p><em>{html.escape(mission.source)}</em></p>", _MD.render(mission.help.strip())]
    if mission.equations:
        out.append("<h4>Model</h4>" + equations_html(mission.equations))
    out.append(f"<h4>Method: {html.escape(method.label)}</h4>"
               f"<p><em>{html.escape(method.source)}</em></p>"
               f"<p>{html.escape(method.summary)}</p>")
    if method.equations:
        out.append(equations_html(method.equations))
    if equations and _latex2mathml is None:
        out.append(MISSING)
    if mission.published:
        rows = "".join(f"<tr><td>{html.escape(p.name)}</td><td>{p.value:g} {html.escape(p.unit)}"
                       f"</td><td>{html.escape(p.source)}</td></tr>" for p in mission.published)
        out.append("<h4>Published numbers</h4><table><tr><th>quantity</th><th>value</th>"
                   f"<th>source</th></tr>{rows}</table>")
    out.append("</div>")
    return "".join(out)
