"""The screen does not lie about state (issue 16), through Debian chromium: the address bar
follows a refinement, a verdict never outlives its case, an answer is not called optimal
before its check, names on screen are labels with units, the time-limit box refuses bad
entries, and a long or malformed link opens the default case with a message."""

from __future__ import annotations

from urllib.parse import parse_qs, urlsplit

from browser_support import BROWSER, PATIENCE_MS, until

pytestmark = BROWSER
VERDICT = "Checked from the initial guess"


def _solved(view, key: str | None = None) -> None:
    until(lambda: view.session.wait_idle(120) and view.session.latest is not None
           and view.session.latest.ok
           and (key is None or view.session.latest.mission == key), "an optimal answer")


def _address(page) -> dict[str, str]:
    query = urlsplit(page.evaluate("() => location.href")).query
    return {k: v[0] for k, v in parse_qs(query).items()}


def _status(page) -> str:
    return page.locator("#explorer-status").inner_text()


def test_the_address_follows_a_refinement_and_restores_it(tab):
    page, view = tab()
    view.session.set_nodes(8)  # 8 intervals miss the 10 cm touchdown target: refined
    until(lambda: view.session.wait_idle(60) and view.session.latest.nodes == 8
           and _address(page).get("nodes") == "8", "the 8-interval case in the address")
    view.session.submit(refine=True)
    until(lambda: view.session.wait_idle(60) and view.session.latest.nodes > 8,
           "the refined answer")
    nodes = view.session.nodes
    until(lambda: _address(page).get("nodes") == str(nodes),
           f"nodes={nodes} in the address (it said {_address(page).get('nodes')})", 20.0)
    page.locator(f"text=intervals {nodes}").first.wait_for(timeout=PATIENCE_MS)  # the status's word
    query = urlsplit(page.evaluate("() => location.href")).query
    _, other = tab(query)
    until(lambda: other.session.nodes == nodes, "the refined node count restored")


def test_a_verdict_is_cleared_with_its_case(tab):
    from solvers import get_mission

    page, view = tab()
    _solved(view)
    page.get_by_text("Accuracy and optimality").first.click()
    view.session.check_from_cold()
    page.get_by_text(VERDICT).first.wait_for(timeout=PATIENCE_MS)
    view.session.select_mission(get_mission("bang-bang"))
    _solved(view, "bang-bang")
    until(lambda: "hermite-simpson" in _status(page) and "final time" in _status(page)
           and "bang" not in view.trust.report.content, "the bang-bang status")
    assert page.get_by_text(VERDICT).count() == 0, "the lander's verdict is still shown"


def test_an_answer_is_not_called_optimal_before_its_check(tab):
    page, view = tab()
    _solved(view)
    shown: list[tuple[object, str]] = []
    show_result = view.status.show_result

    def spy(sol, *args, **kwargs):
        show_result(sol, *args, **kwargs)
        shown.append((sol, view.status.result_md))

    view.status.show_result = spy
    view.session.set_value("thrust", 2500.0)
    until(lambda: view.session.wait_idle(60) and view.session.latest.values["thrust"] == 2500.0
           and len(shown) >= 2, "the new answer and its check")
    first, last = shown[0][1], shown[-1][1]
    assert "converged · checking…" in first and "**optimal**" not in first, first
    assert "**optimal**" in last and "checking" not in last, last
    until(lambda: "optimal" in _status(page), "the checked status on the page")


def test_read_outs_are_labels_and_a_prefixed_unit_is_taken(tab):
    page, view = tab()
    _solved(view)
    box = _box_with(page, "2000")  # thrust [N]
    box.fill("3 kN")  # where "2500 N" is taken
    until(lambda: view.session.values["thrust"] == 3000.0, "3 kN taken as 3000 N")
    page.get_by_role("tab", name="Play").click()
    page.get_by_text("radial speed").first.wait_for(timeout=PATIENCE_MS)
    text = page.locator("body").inner_text()
    rows = {line.split("\t")[0].strip() for line in text.splitlines() if "\t" in line}
    for raw in ("v", "theta", "omega", "control psi"):
        assert raw not in rows, f"the read-out '{raw}' is a raw name"
    assert "thrust angle above the horizontal" in rows


def test_the_comparison_table_reads_well_and_fits_beside_the_scrollbar(tab):
    page, view = tab()
    _solved(view)
    page.get_by_role("tab", name="Compare").click()
    view.session.compare(["hermite-simpson", "multiple-shooting"])
    table = page.locator("#comparison-table")
    table.wait_for(timeout=PATIENCE_MS)
    cells = table.locator("td").all_inner_texts()
    assert not [c for c in cells if "e-" in c or "e+" in c], cells  # no 1.12086e-26
    assert "< 1 mm" in cells  # the final altitude of a converged landing
    assert table.locator("td").nth(1).evaluate("e => getComputedStyle(e).whiteSpace") \
        == "nowrap"
    hidden = page.evaluate("""() => {
      const table = document.querySelector('#comparison-table');
      const box = table.parentElement;
      box.scrollLeft = box.scrollWidth;  // a wide table scrolled to its last column
      const root = table.closest('.mantine-ScrollArea-root');
      const bar = [...root.querySelectorAll('.mantine-ScrollArea-scrollbar')].find(
          (b) => b.dataset.orientation === 'vertical' && b.getBoundingClientRect().width > 0);
      const right = bar ? bar.getBoundingClientRect().left : root.getBoundingClientRect().right;
      return [...table.querySelectorAll('th')].filter(
          (th) => th.getBoundingClientRect().right > right + 0.5).map((th) => th.textContent);
    }""")
    assert not hidden, f"columns under the panel's scrollbar: {hidden}"


def _box_with(page, text: str):
    """The visible typed-value box that shows `text`."""
    element = page.evaluate_handle(
        "(text) => [...document.querySelectorAll('input')].find("
        "(i) => i.value === text && i.offsetParent !== null)", text).as_element()
    assert element is not None, f"no box shows {text!r}"
    element.scroll_into_view_if_needed()
    return element


def test_the_time_limit_box_refuses_bad_entries(tab):
    page, view = tab()
    _solved(view)
    page.get_by_role("tab", name="Export").click()
    label = page.get_by_text("solve time limit [s]", exact=True).first
    label.wait_for(timeout=PATIENCE_MS)
    box = label.locator("xpath=ancestor::div[.//input][1]//input").first
    before = view.session.time_limit
    shown = box.input_value()
    assert float(shown) == before
    for typed, said in (("-5", "-5 s"), ("1e999", "inf s"), ("0.0001", "0.0001 s")):
        box.fill(typed)
        page.get_by_text(f"{said} is outside the allowed range: enter a time from 0.1 to "
                         "600 s").first.wait_for(timeout=PATIENCE_MS)
        until(lambda: box.input_value() == shown, f"the old limit back after {typed!r}")
        assert view.session.time_limit == before
    box.fill("12 s")
    until(lambda: view.session.time_limit == 12.0, "a good limit taken")
    box.fill(shown)
    until(lambda: view.session.time_limit == before, "the limit put back")


def test_a_long_or_malformed_link_opens_the_default_case_with_a_message(tab):
    from solvers import get_mission

    default = get_mission("lunar-landing").defaults("hermite-simpson")["thrust"]
    page, view = tab("mission=lunar-landing&v.thrust=" + "1" * 10_000)  # over 8 kB
    page.get_by_text("the link is too long").first.wait_for(timeout=PATIENCE_MS)
    assert view.session.values["thrust"] == default
    page, view = tab("mission=lunar-landing&nodes=%C2%B2")  # nodes=²
    page.get_by_text("is not a whole number").first.wait_for(timeout=PATIENCE_MS)
    assert view.session.nodes == get_mission("lunar-landing").method("hermite-simpson").nodes[1]


# In the page, before viser's page starts: every batch of messages its websocket worker
# hands to the page, as (message type, scene node, the text a GUI update sets).
_BATCHES = """(() => {
  window.__batches = [];
  const Original = window.Worker;
  window.Worker = function (...args) {
    const worker = new Original(...args);
    worker.addEventListener('message', (event) => {
      if (!event.data || event.data.type !== 'message_batch') return;
      window.__batches.push(event.data.messages.map((m) => [
        m.type, m.name || '', JSON.stringify((m.updates && m.updates.content) || '')]));
    });
    return worker;
  };
  window.Worker.prototype = Original.prototype;
})();"""


def test_the_words_of_an_answer_reach_the_page_before_its_picture(tab, app):
    """The status of a new answer leaves in a batch of its own, before the batch that moves
    the path: viser's page applies a batch of GUI messages at once but holds one that
    touches the scene for its next 3D frame, so sent with (or after) the scene the new
    numbers waited a software frame or two."""
    from explorer.panels.status import fmt

    app.context.add_init_script(_BATCHES)
    page, view = tab()
    _solved(view)
    until(lambda: "checking" not in _status(page), "the first answer's check")
    page.evaluate("() => { window.__batches = []; }")
    before = view.session.latest
    view.session.set_value("thrust", 2100.0)
    until(lambda: view.session.wait_idle(60) and view.session.latest is not before
           and view.session.latest.ok, "the new answer")
    cost = fmt(view.session.latest.cost.value, view.session.latest.cost.unit)

    def batches():
        found = page.evaluate("() => window.__batches")
        words = next((i for i, b in enumerate(found)  # the answer's, not its check's
                      if any(cost in m[2] and "checking" in m[2] for m in b)), None)
        path = next((i for i, b in enumerate(found)  # the new nodes (a dimmed path has none)
                     if any(m[1].startswith("/nodes") for m in b)), None)
        return None if words is None or path is None else (found, words, path)

    found, words, path = until(batches, "the new status and nodes in the page")
    assert words < path, f"the status came in batch {words}, the new nodes in batch {path}"
    assert all(not m[0].startswith(("SceneNode", "Set")) for m in found[words]), found[words]
