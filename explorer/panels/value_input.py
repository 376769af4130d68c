"""A parameter's control: a slider to drag and a box to type a value into.

The box forgives: it takes what a person types (`1e4`, `2,500`, `2500 N`), waits until the
typing has paused (`COMMIT_AFTER`) instead of solving every keystroke, and refuses an empty,
non-numeric or out-of-range entry with a message that names the range, putting the old value
back — it never clamps silently. The slider's own number box (which commits every keystroke
and clamps) is hidden by the page style in `style.py`. Values are shown in the parameter's
display unit; the session always receives SI.
"""

from __future__ import annotations

import datetime as dt
import math
import re
import threading
from collections.abc import Callable
from typing import Any

import viser

from solvers.problem import Param

COMMIT_AFTER = 0.8  # s without typing before a typed value is used
Apply = Callable[[str, float], None]  # (param key, SI value)
Report = Callable[[str, str], None]  # (title, message)


ECHO = 40  # characters of a refused entry repeated in its message


def echo(text: str) -> str:
    """`text` as a message repeats it: at most `ECHO` characters (a pasted page is not
    echoed back in full)."""
    return text if len(text) <= ECHO else f"{text[:ECHO - 1]}… ({len(text)} characters)"


def clean(x: float) -> float:
    """Drop binary noise from a unit conversion (0.9650000000000001 -> 0.965)."""
    return float(f"{x:.12g}")


def display_unit(p: Param) -> str:
    return p.display_unit if p.display_unit is not None else p.unit


def label_of(p: Param) -> str:
    if p.epoch is not None:
        return f"{p.label} [days from {p.epoch}]"
    unit = display_unit(p)
    return f"{p.label} [{unit}]" if unit and not p.options else p.label


def to_display(p: Param, si: float) -> float:
    return clean(si * p.display_factor)


def from_display(p: Param, shown: float) -> float:
    """SI value of a shown value, clamped to [min, max] against round-off of the factor."""
    si = min(max(shown / p.display_factor, p.min), p.max)
    if p.integer or p.options:
        return float(round(si))
    lo_gap, hi_gap = abs(si - p.min), abs(si - p.max)
    tol = 1e-9 * max(abs(p.min), abs(p.max), abs(p.step))
    return float(p.min if lo_gap < tol else p.max if hi_gap < tol else clean(si))


def display_range(p: Param) -> tuple[float, float, float]:
    """(min, max, step) of the slider in display units."""
    lo, hi = sorted((to_display(p, p.min), to_display(p, p.max)))
    return lo, hi, clean(abs(p.step * p.display_factor))


def shown_text(p: Param, si: float) -> str:
    """The box's text for an SI value: the display value, no binary noise; a date for a
    day count from an epoch."""
    if p.epoch is not None:
        day = dt.date.fromisoformat(p.epoch) + dt.timedelta(days=round(si))
        return day.isoformat()
    return f"{to_display(p, si):.10g}"


PREFIXES = {"": 1.0, "k": 1e3, "M": 1e6, "G": 1e9, "c": 1e-2, "m": 1e-3, "µ": 1e-6,
            "u": 1e-6}
_TYPED_UNIT = re.compile(r"^(.*?[\d.](?:[eE][-+]?\d+)?)\s*([^\W\d_]\S*|°|%)$")


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _typed_unit(raw: str, unit: str) -> tuple[str, float | None]:
    """(number text, factor to the display unit) of an entry with or without a trailing
    unit: "3 kN" in N is ("3", 1000); a unit that is no SI prefix of `unit` gives None."""
    match = _TYPED_UNIT.match(raw)
    if match is None or _is_number(raw):
        return raw, 1.0
    number, typed = match.group(1), match.group(2)
    if typed == unit:
        return number, 1.0
    for shown_prefix, shown_factor in PREFIXES.items():
        base = unit[len(shown_prefix):] if unit.startswith(shown_prefix) else None
        if not base or any(power in base for power in "²³^"):  # km² is not 1000 m²
            continue
        for typed_prefix, typed_factor in PREFIXES.items():
            if typed == typed_prefix + base:
                return number, typed_factor / shown_factor
    return number, None


def parse_typed(p: Param, text: str) -> float:
    """The SI value of what a person typed, or `ValueError` with a message naming the range
    in display units. Takes scientific notation, thousands separators and a trailing unit."""
    lo, hi, _ = display_range(p)
    unit = display_unit(p)
    allowed = f"enter a value from {lo:g} to {hi:g}" + (f" {unit}" if unit else "")
    raw = text.strip()
    if p.epoch is not None:
        first, last = shown_text(p, p.min), shown_text(p, p.max)
        try:
            days = (dt.date.fromisoformat(raw) - dt.date.fromisoformat(p.epoch)).days
        except ValueError:
            pass  # not a date: maybe a day count
        else:
            if not p.min <= days <= p.max:
                raise ValueError(f"{echo(raw)} is outside the allowed dates: {first} to "
                                 f"{last}")
            return float(days)
        allowed = f"enter a date from {first} to {last} (YYYY-MM-DD) or a day count"
    raw, factor = _typed_unit(raw, unit)
    if factor is None:
        raise ValueError(f"'{echo(text.strip())}' is not in {unit}: {allowed}")
    raw = re.sub(r"(?<=\d)[,_ ](?=\d{3})", "", raw)
    try:
        shown = float(raw) * factor
    except ValueError:
        what = "an empty box" if not raw else f"'{echo(text.strip())}'"
        raise ValueError(f"{what} is not a number: {allowed}") from None
    if not math.isfinite(shown):
        raise ValueError(f"'{echo(text.strip())}' is not a finite number: {allowed}")
    if not lo - 1e-12 * max(abs(lo), abs(hi), 1.0) <= shown <= hi + 1e-12 * max(abs(lo),
                                                                                  abs(hi), 1.0):
        raise ValueError(f"{shown:g} is outside the allowed range: {allowed}")
    if (p.integer or p.options) and shown / p.display_factor != round(shown / p.display_factor):
        raise ValueError(f"{shown:g} is not a whole number: {allowed}")
    return from_display(p, shown)


TIME_LIMIT_RANGE = (0.1, 600.0)  # s: shorter stops every solve, longer is "no limit"
NO_LIMIT = ("0", "none", "no limit", "off")


def parse_time_limit(text: str) -> float | None:
    """The solve time limit typed (s; `None`: no limit, typed as 0 or "no limit"), or
    `ValueError` naming the range, like a parameter's box: never a silent "no limit"."""
    lo, hi = TIME_LIMIT_RANGE
    allowed = f"enter a time from {lo:g} to {hi:g} s, or 0 for no limit"
    raw = text.strip().lower()
    if raw in NO_LIMIT:
        return None
    number = raw[:-1].strip() if raw.endswith("s") else raw
    try:
        seconds = float(number)
    except ValueError:
        what = "an empty box" if not raw else f"'{echo(text.strip())}'"
        raise ValueError(f"{what} is not a number: {allowed}") from None
    if seconds == 0:
        return None
    if not (math.isfinite(seconds) and lo <= seconds <= hi):
        raise ValueError(f"{seconds:g} s is outside the allowed range: {allowed}")
    return seconds


class Pause:
    """Runs `action` once typing has paused for `delay` s: each keystroke restarts the wait."""

    def __init__(self, action: Callable[[], None], delay: float = COMMIT_AFTER) -> None:
        self.action, self.delay = action, delay
        self._timer: threading.Timer | None = None
        self._lock = threading.Lock()

    def restart(self) -> None:
        with self._lock:
            if self._timer is not None:
                self._timer.cancel()
            self._timer = threading.Timer(self.delay, self.action)
            self._timer.daemon = True
            self._timer.start()

    def cancel(self) -> None:
        with self._lock:
            if self._timer is not None:
                self._timer.cancel()
                self._timer = None


class NumberField:
    """Slider plus typed-value box for one numeric `Param`; `apply(key, si)` receives every
    accepted value, `report(title, message)` every refused one."""

    def __init__(self, gui: viser.GuiApi, p: Param, value: float, apply: Apply,
                 report: Report, hint: str | None = None) -> None:
        self.param, self.apply, self.report = p, apply, report
        self.value = float(value)
        lo, hi, step = display_range(p)
        self.slider = gui.add_slider(label_of(p), lo, hi, step, to_display(p, value), hint=hint)
        self.box = gui.add_text(" ", shown_text(p, value),
                                hint=f"Type a value ({lo:g} to {hi:g} {display_unit(p)}); "
                                     "it is used when you stop typing.")
        self._syncing = False
        self._pause = Pause(self.commit)
        self.slider.on_update(self._slid)
        self.box.on_update(self._typed)

    @property
    def handle(self) -> Any:
        """The slider (what tests and other code read and move)."""
        return self.slider

    def show(self, value: float, box: bool = True) -> None:
        """Show an SI value in the slider (and the box unless `box` is off) without applying
        it again."""
        self.value = float(value)
        self._syncing = True
        try:
            self.slider.value = to_display(self.param, value)
            if box:
                self.box.value = shown_text(self.param, value)
        finally:
            self._syncing = False

    def _slid(self, _: Any) -> None:
        if self._syncing:
            return
        shown = float(self.slider.value)
        if not math.isfinite(shown):
            return
        self.value = from_display(self.param, shown)
        self._syncing = True
        try:
            self.box.value = shown_text(self.param, self.value)
        finally:
            self._syncing = False
        self.apply(self.param.key, self.value)

    def _typed(self, _: Any) -> None:
        if not self._syncing:
            self._pause.restart()

    def commit(self) -> None:
        """Use the typed text now (after the pause, or at once from tests)."""
        self._pause.cancel()
        text = str(self.box.value)
        if text == shown_text(self.param, self.value):
            return
        try:
            value = parse_typed(self.param, text)
        except ValueError as exc:
            self.report(self.param.label, str(exc))
            self.show(self.value)  # the old value stays, in both widgets
            return
        if value == self.value:
            return
        # The slider follows; the box keeps the text as typed. Writing it back in canonical
        # form could reach the page after a newer entry and overwrite what the user typed.
        self.show(value, box=False)
        self.apply(self.param.key, value)


class TimeLimitField:
    """A typed box for the solve time limit: used when the typing pauses, refused in words
    (the range) with the old value put back, like a parameter's box."""

    def __init__(self, gui: viser.GuiApi, label: str, seconds: float | None,
                 apply: Callable[[float | None], None], report: Report, hint: str) -> None:
        self.apply, self.report = apply, report
        self.seconds = seconds
        self.box = gui.add_text(label, self.text(seconds), hint=hint)
        self._pause = Pause(self.commit)
        self.box.on_update(self._typed)

    @staticmethod
    def text(seconds: float | None) -> str:
        return "0" if seconds is None else f"{seconds:g}"

    def _typed(self, _: Any) -> None:
        self._pause.restart()

    def commit(self) -> None:
        """Use the typed text now (after the pause, or at once from tests)."""
        self._pause.cancel()
        text = str(self.box.value)
        try:
            seconds = parse_time_limit(text)
        except ValueError as exc:
            self.report("solve time limit", str(exc))
            self.box.value = self.text(self.seconds)
            return
        if seconds == self.seconds:
            return
        # The box keeps the text as typed ("12 s"): an echo in canonical form could reach
        # the page after a newer entry and overwrite it.
        self.seconds = seconds
        self.apply(seconds)
