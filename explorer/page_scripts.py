"""Scripts the explorer runs in the page through viser's HTML element, which runs no
<script>: an image whose source is not an image runs its `onerror` at once (a new source each
time, so a re-render runs it again). Two hidden text boxes use them to hand the page's
address to the server: the case link and the teacher key."""

from __future__ import annotations

import html
import itertools
import json

_nonce = itertools.count()

# Finds the viser text box labelled `label`, hides its row, and fills it as a person would
# type (React listens to the native setter and an input event).
_HIDDEN_BOX = """
  const label = [...document.querySelectorAll('label')].find(
      (l) => l.textContent.trim() === LABEL);
  let row = label, input = null;
  for (let i = 0; i < 5 && row && !input; i++) {
    row = row.parentElement;
    input = row && row.querySelector('input');
  }
  if (!input) return;
  if (row.parentElement) row.parentElement.style.display = 'none';
  const fill = (value) => {
    const setter = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, 'value').set;
    setter.call(input, value);
    input.dispatchEvent(new Event('input', {bubbles: true}));
  };
"""


def run_once_html(js: str) -> str:
    """HTML that runs `js` once each time it is rendered (then marks its image
    `data-ran`, which tests wait for)."""
    return (f'<img src="data:,{next(_nonce)}" style="display:none" '
            f'onerror="{html.escape(js)};this.dataset.ran = 1;">')


def hidden_box_html(label: str, body: str, before: str = "") -> str:
    """HTML that runs `before`, then finds and hides the box labelled `label` and runs
    `body`, which may call `fill(value)` to send a value through the box."""
    return run_once_html("(function () {" + before + _HIDDEN_BOX.replace(
        "LABEL", json.dumps(label)) + body + "})();")
