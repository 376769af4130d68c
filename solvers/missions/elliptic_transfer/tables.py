"""The help's tables, generated from code (never pasted): our cost beside the paper's, and the
convergence of the laws with the LGL degree N, both against the Gramian reference, for the
paper case (the mission's defaults). Computed once per process (about 0.4 s) so the About
panel stays fast."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from ...problem import Published
from .laws import solve_law
from .model import gramian_cost, make_case
from .problem import PARAMS

CONVERGENCE_NODES = (8, 16, 24, 32, 48, 64, 96, 128)
LAWS = ("stm-f", "seq-f", "seq-t")  # STM law (f), SEQ law (f), SEQ law (time t)
PAPER_N = 64


@dataclass(frozen=True)
class Convergence:
    """J [m²/s³] of each law per LGL degree N for one case, and the Gramian reference."""

    J_gramian: float
    k2: float
    rows: tuple[tuple[int, tuple[float, ...]], ...]  # (N, J per law in LAWS order)

    def at(self, N: int) -> tuple[float, ...]:
        """J per law (LAWS order) at degree N."""
        return dict(self.rows)[N]


@cache
def paper_convergence() -> Convergence:
    """The laws' J per N in `CONVERGENCE_NODES` for the paper case (computed once)."""
    case = make_case({p.key: p.default for p in PARAMS})
    rows = tuple((N, tuple(solve_law(case, law, N).J for law in LAWS))
                 for N in CONVERGENCE_NODES)
    return Convergence(gramian_cost(case), case.orbit.k2, rows)


def sci(value: float, digits: int) -> str:
    """Scientific notation without exponent padding: 3.75854e-4."""
    mantissa, exponent = f"{value:.{digits - 1}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def short(value: float) -> str:
    """A printed number as the paper prints it: 1.9e-6."""
    mantissa, _, exponent = f"{value:g}".partition("e")
    return f"{mantissa}e{int(exponent)}" if exponent else mantissa


def _relative(J: float, reference: float) -> str:
    r = (J - reference) / reference
    return f"{r:+.0e}" if abs(r) > 1e-9 else "< 1e-9"


def convergence_markdown(conv: Convergence) -> str:
    """J per N (relative error against the Gramian value in brackets)."""
    rows = ["| N | STM law (f) | SEQ law (f) | SEQ law (time t) |", "|---|---|---|---|"]
    for N, Js in conv.rows:
        cells = [f"{sci(J, 5)} ({_relative(J, conv.J_gramian)})" for J in Js]
        rows.append(f"| {N} | " + " | ".join(cells) + " |")
    return "\n".join(rows)


def cost_markdown(conv: Convergence, published: tuple[Published, ...]) -> str:
    """Ours (Gramian and both laws at the paper's N) beside the paper's printed values."""
    printed = {pub.methods[0]: pub for pub in published if pub.name == "J_f"}
    J_stm, J_seq, _ = conv.at(PAPER_N)
    rows = [
        "| | J = ½∫\\|u\\|² dt [m²/s³] | J_f = k² J [m²/s⁴] | relative to the Gramian "
        "| paper, printed \"m²/s\" |",
        "|---|---|---|---|---|",
        f"| Gramian (exact) | {sci(conv.J_gramian, 6)} | {sci(conv.k2 * conv.J_gramian, 5)} "
        "| — | — |",
    ]
    for label, key, J in (("STM law", "stm-law", J_stm), ("SEQ law", "seq-law", J_seq)):
        pub = printed[key]
        verdict = "" if pub.holds else " (does not hold)"
        rows.append(f"| {label}, N = {PAPER_N} | {sci(J, 6)} | {sci(conv.k2 * J, 5)} "
                    f"| {_relative(J, conv.J_gramian)} | {short(pub.value)}{verdict} |")
    return "\n".join(rows)
