"""Help where a newcomer needs it: a three-line welcome at the top of the panel (dismissible)
and the keys in a window that `?` opens."""

from __future__ import annotations

import viser

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


class KeyHelp:
    """`?` opens the keys in a window, in the browser that pressed it."""

    def __init__(self, gui: viser.GuiApi) -> None:
        command = gui.add_command("Keys and help", hotkey="?", icon=viser.Icon.HELP)
        command.on_trigger(lambda event: self.open(event.client))

    @staticmethod
    def open(client: viser.ClientHandle | None) -> None:
        if client is None:
            return
        with client.gui.add_modal("Keys and help") as modal:
            client.gui.add_markdown(KEYS)
            client.gui.add_button("close").on_click(lambda _: modal.close())
