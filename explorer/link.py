"""A link that restores a case: the page's address always carries the case on screen (mission,
method, back end, nodes, the values and view options that differ from the defaults), so a
person copies it from the address bar or the Export tab and anyone who opens it sees the same
case.

viser sends no page address to the server, so two small scripts run in the page (an HTML
element's `onerror`, the one way viser's HTML runs code): one writes the case into the address
bar (`history.replaceState`) whenever it changes; one reads the address once when the page
opens and hands its query to a hidden text box, whose update the server turns into
`Session.restore`. Only numbers and keys are read from the address: nothing a browser sends is
evaluated.
"""

from __future__ import annotations

import json
import secrets
from collections.abc import Callable
from urllib.parse import parse_qsl, urlencode

import viser
import websockets.http11

from solvers.mission import Mission

from .page_scripts import hidden_box_html, run_once_html
from .panels.value_input import echo
from .session import Session

BOX_LABEL = "case from the link"
MAX_LINK = 4000  # characters of a query the page hands over: a case needs a few hundred
TOO_LONG = "too-long="  # what the page hands over instead of a longer query (+ its length)
# viser serves its page through websockets' HTTP parser, which closes the connection on a
# request line over 8 kB without an answer (a blank page, ERR_EMPTY_RESPONSE). Up to
# chromium's own limit on an address (2 MB) the page loads instead, and says the link is
# too long.
websockets.http11.MAX_LINE_LENGTH = max(websockets.http11.MAX_LINE_LENGTH, 2 * 2**20)


def case_query(session: Session) -> str:
    """The case as a query string: mission, method, back end, nodes, changed values (SI)."""
    mission = session.mission
    items = [("mission", mission.key), ("method", session.method), ("nodes", session.nodes)]
    if session.backend and session.backend != mission.method(session.method).default_backend:
        items.append(("backend", session.backend))
    defaults = mission.defaults(session.method)
    items += [(f"v.{k}", f"{v:.12g}") for k, v in session.values.items() if v != defaults.get(k)]
    view_defaults = mission.view_defaults()
    items += [(f"w.{k}", f"{v:.12g}") for k, v in session.view.items()
              if v != view_defaults.get(k)]
    return urlencode(items)


def parse_case(query: str, missions: dict[str, Mission]
               ) -> tuple[Mission, str | None, int | None, str | None, dict, dict]:
    """(mission, method, nodes, backend, values, view) from a query; `ValueError` names
    what is wrong. Values must be numbers; the session validates their ranges."""
    length = query[len(TOO_LONG):] if query.startswith(TOO_LONG) else len(query)
    if query.startswith(TOO_LONG) or len(query) > MAX_LINK:
        raise ValueError(f"the link is too long ({echo(str(length))} characters; a case "
                         f"needs at most {MAX_LINK}): the default case is shown")
    fields = dict(parse_qsl(query.lstrip("?"), keep_blank_values=True))
    key = fields.get("mission")
    if key not in missions:
        raise ValueError(f"the link names no known mission ('{echo(str(key))}')")
    values, view = {}, {}
    for name, raw in fields.items():
        if name.startswith(("v.", "w.")):
            try:
                number = float(raw)
            except ValueError:
                raise ValueError(f"the link's {echo(name[2:])} = '{echo(raw)}' is not a "
                                 "number") from None
            (values if name[0] == "v" else view)[name[2:]] = number
    nodes = fields.get("nodes")
    if nodes is not None and not (nodes.isascii() and nodes.isdigit()):
        raise ValueError(f"the link's nodes = '{echo(nodes)}' is not a whole number")
    mission = missions[key]
    method = fields.get("method")
    if method is not None and method not in {m.key for m in mission.methods}:
        raise ValueError(f"the link names no method '{echo(method)}' of {key}")
    known = {p.key for m in mission.methods for p in mission.all_params(m.key)}
    unknown = [k for k in values if k not in known] + [
        k for k in view if k not in {p.key for p in mission.view_params}]
    if unknown:
        raise ValueError(f"the link names no parameter '{echo(unknown[0])}' of {key}")
    return (mission, method, int(nodes) if nodes else None,
            fields.get("backend"), values, view)




def address_html(query: str, token: str) -> str:
    """HTML whose script puts `query` into the address bar (and shows nothing), and keeps
    it as the case last shown by the tab's connection `token` (see `READ_ADDRESS`)."""
    return run_once_html(
        f"history.replaceState(null, '', '?' + {json.dumps(query)});"
        "const shown = (window.__explorerCases = window.__explorerCases || []);"
        f"const i = shown.findIndex((e) => e[0] === {json.dumps(token)});"
        "if (i >= 0) shown.splice(i, 1);"
        f"shown.push([{json.dumps(token)}, {json.dumps(query)}]);")


# Sends the opening address through the hidden box once per connection (a link that is too
# long is refused with its length). Not the address bar: this connection's writer may
# already have put its own session's case there (a student who opened the room's link read
# the teacher's case, and restoring it branched the student off the room), and the reader
# runs again whenever the page re-renders it. So: the address the page was opened with (its
# navigation entry), or after a reconnection the case the page showed last, as the earlier
# connection's writer kept it. (`window.URL`: in an inline handler `URL` is document.URL.)
READ_ADDRESS = """
  if (window.__explorerCaseRead === TOKEN) return;
  window.__explorerCaseRead = TOKEN;
  const before = (window.__explorerCases || []).filter((e) => e[0] !== TOKEN).pop();
  const opened = performance.getEntriesByType('navigation')[0];
  let query = before ? before[1]
      : (opened ? new window.URL(opened.name).search : window.location.search).slice(1);
  if (!query.includes('mission=')) return;
  if (query.length > MAX_LINK) query = TOO_LONG + query.length;
  fill(query);
"""


class CaseLink:
    """The hidden box that receives the opening address, and the element that keeps the
    address bar up to date. `restore(query)` is called with what the page's address held."""

    def __init__(self, gui: viser.GuiApi, restore: Callable[[str], None]) -> None:
        self.box = gui.add_text(BOX_LABEL, "", order=-99)
        self.box.on_update(lambda _: restore(str(self.box.value)) if self.box.value else None)
        self.token = secrets.token_hex(8)  # this tab's connection (see READ_ADDRESS)
        body = READ_ADDRESS.replace("MAX_LINK", str(MAX_LINK)).replace(
            "TOO_LONG", json.dumps(TOO_LONG)).replace("TOKEN", json.dumps(self.token))
        self.reader = gui.add_html(hidden_box_html(BOX_LABEL, body), order=-98)
        self.writer = gui.add_html("", order=-97)
        self._query = ""

    def show(self, query: str) -> None:
        """Put `query` into the address bar of every page watching."""
        if query != self._query:
            self._query = query
            self.writer.content = address_html(query, self.token)
