"""The legend under the status line: what the colours in the 3D view mean (burn/coast arcs
or the colour bar of `Presentation.color_by`, nodes, the arrows (each under the name its
presentation gives the arcs and arrows: a reentry's are no thrust), every reference curve
(dashed ones dashed) and body, a dimmed or failed trajectory, a comparison's methods)."""

from __future__ import annotations

import html
from collections.abc import Sequence

from .geometry import (
    ARROW,
    BURN,
    COAST,
    NODE,
    NODE_LIGHT,
    WARNING,
    ColorBar,
    Geometry,
    colorbar_css,
)

STYLE = ("<style>.lg{font-size:0.78em;line-height:1.5}.lg span.sw{display:inline-block;"
         "width:14px;height:4px;margin:0 4px 2px 0;vertical-align:middle;border-radius:1px}"
         ".lg .it{margin-right:10px;white-space:nowrap}.lg .bar{height:8px;border-radius:2px;"
         "margin:2px 0}.lg .ends{display:flex;justify-content:space-between}</style>")


def _item(rgb: Sequence[int], label: str, dot: bool = False, dashed: bool = False) -> str:
    shape = "width:7px;height:7px;border-radius:50%" if dot else ""
    if dashed:
        color = f"rgb{tuple(rgb)}"
        shape = (f"background:repeating-linear-gradient(to right,{color} 0 3px,"
                 "transparent 3px 5px)")
        return (f'<span class="it"><span class="sw" style="{shape}"></span>'
                f"{html.escape(label)}</span>")
    return (f'<span class="it"><span class="sw" style="background:rgb{tuple(rgb)};{shape}">'
            f"</span>{html.escape(label)}</span>")


def _colorbar(bar: ColorBar) -> str:
    unit = f" [{bar.unit}]" if bar.unit else ""
    return (f"<div>path coloured by <b>{html.escape(bar.name)}</b>{html.escape(unit)}</div>"
            f'<div class="bar" style="background:{colorbar_css()}"></div>'
            f'<div class="ends"><span>{bar.lo:.4g}</span><span>{bar.hi:.4g}</span></div>')


def legend_html(g: Geometry, dim: bool = False, failed: bool = False,
                comparison: Sequence[tuple[str, tuple[int, int, int]]] | None = None,
                dark: bool = True) -> str:
    """The legend as HTML for the current drawing."""
    items: list[str] = []
    if comparison:
        items += [_item(c, name) for name, c in comparison]
    else:
        if dim:
            items.append(_item((110, 110, 110), "last good (dimmed)"))
        elif g.colorbar is not None:
            items.append(_colorbar(g.colorbar))
        else:
            kinds = {tuple(c) for c in g.segment_colors[:, 0].tolist()}
            for color, kind in ((BURN, "burn"), (COAST, "coast")):
                if tuple(color) in kinds:
                    items.append(_item(color, g.arc_names.get(kind, f"{kind} arc")))
        if failed:
            items.append(_item(WARNING, "failed attempt"))
    if len(g.nodes) and not comparison:
        items.append(_item(NODE if dark else NODE_LIGHT, "nodes", dot=True))
    if len(g.arrows) and not comparison:
        items.append(_item(ARROW, g.arrow_name))
    curves = dict.fromkeys(g.curve_names)  # each kind once, however many pieces it has
    items += [_item(color, name, dashed=dashed) for name, color, dashed in curves]
    items += [_item(s.color, s.name, dot=True) for s in g.spheres]
    return f'{STYLE}<div class="lg">{"".join(items)}</div>'
