"""The page's own style sheet, put in once per GUI through an HTML element: it hides the
number box viser puts beside every slider (it commits each keystroke and clamps silently;
our `NumberField` box replaces it) and keeps wide content (equations, tables) inside the
panels."""

from __future__ import annotations

import viser

PAGE_CSS = """<style>
.mantine-Slider-root + .mantine-NumberInput-root { display: none !important; }
.about .eq, .about table { max-width: 100%; overflow-x: auto; display: block; }
#explorer-status { font-size: 0.9em; line-height: 1.45; }
#explorer-status p { margin: 0.15em 0; }
#explorer-status .hint { opacity: 0.8; font-style: italic; }
.explorer-welcome { font-size: 0.85em; line-height: 1.4; padding: 0.4em 0.6em;
  border-left: 3px solid #ff8c00; margin: 0.2em 0 0.4em 0; }
</style>"""


def install(gui: viser.GuiApi) -> viser.GuiHtmlHandle:
    """Add the style sheet to this GUI (first element, empty on screen)."""
    return gui.add_html(PAGE_CSS, order=-100)
