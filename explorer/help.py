"""Help where a newcomer needs it: a three-line welcome at the top of the panel (dismissible)
and the keys in a window that `?` opens; and the keys kept where the hand is: an arrow key
on a focused slider steps the slider only."""

from __future__ import annotations

import json

import viser

from .page_scripts import run_once_html

WELCOME = """<div class="explorer-welcome"><b>Trajectory explorer:</b> each picture is the
optimum of a trajectory-optimisation problem, solved live.<br>
Move a slider in <b>Setup</b> (or type a value in the box under it): the optimum is solved
again and drawn.<br>
<b>Play</b> flies it, <b>Compare</b> solves it with other methods, <b>?</b> shows the keys.
</div>"""

KEYS = """| key | what it does |
|---|---|
| **space** | play / pause the animation |
| **r** | reset the camera to the overview |
| **?** | this help |
| **ctrl-k** | command palette |
| drag in the view | orbit the camera (scroll: zoom; right-drag: pan) |
| **arrows**, **w a s d q e** | move the camera (click the view first: a control keeps them) |
| **arrows** on a slider | step the slider |

A value typed in a box is used when you stop typing; a value outside the range is refused
with a message and the old value stays. The address bar always holds a link to the case on
screen: copy it to share the case.
"""


class Welcome:
    """The welcome lines and their dismiss button."""

    def __init__(self, gui: viser.GuiApi) -> None:
        self.text = gui.add_html(WELCOME, order=-10)
        self.button = gui.add_button("got it", icon=viser.Icon.CHECK, order=-9,
                                     hint="Hide the welcome (? shows the keys any time).")
        self.button.on_click(lambda _: self.dismiss())

    def dismiss(self) -> None:
        self.text.visible = self.button.visible = False


# viser's page moves the camera on these keys unless they are typed into a form element; a
# slider's thumb (a div) or a tab is not one, so an arrow pressed to step a slider also turned
# the camera, which a re-framing then kept (an off-centre view). Stopped on the way up at the
# body, after the control has had the key and before viser's listener on the document.
CAMERA_KEYS = ("KeyW", "KeyA", "KeyS", "KeyD", "KeyQ", "KeyE",
               "ArrowUp", "ArrowDown", "ArrowLeft", "ArrowRight")
KEEP_KEYS_ON_CONTROLS = """
if (!window.__explorerKeys) {
  window.__explorerKeys = true;
  const keys = new Set(CAMERA_KEYS);
  document.body.addEventListener('keydown', (event) => {
    const target = event.target;
    if (keys.has(event.code) && target !== document.body && target.tagName !== 'CANVAS') {
      event.stopPropagation();
    }
  });
}
"""


class KeyHelp:
    """`?` opens the keys in a window, in the browser that pressed it; the camera's keys
    reach the camera only when no control has the focus."""

    def __init__(self, gui: viser.GuiApi) -> None:
        command = gui.add_command("Keys and help", hotkey="?", icon=viser.Icon.HELP)
        command.on_trigger(lambda event: self.open(event.client))
        self.guard = gui.add_html(run_once_html(KEEP_KEYS_ON_CONTROLS.replace(
            "CAMERA_KEYS", json.dumps(CAMERA_KEYS))), order=-96)

    @staticmethod
    def open(client: viser.ClientHandle | None) -> None:
        if client is None:
            return
        with client.gui.add_modal("Keys and help") as modal:
            client.gui.add_markdown(KEYS)
            client.gui.add_button("close").on_click(lambda _: modal.close())
