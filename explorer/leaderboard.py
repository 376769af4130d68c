"""A challenge's leaderboard (presenter mode): each student's best verified optimum."""

from __future__ import annotations

import threading
from dataclasses import dataclass

from solvers.solution import Solution

from .room_session import Challenge


@dataclass(frozen=True)
class Entry:
    """One student's best admitted solution of a challenge."""

    member: int
    name: str
    solution: Solution

    @property
    def cost(self) -> float:
        return float(self.solution.cost.value)


class Leaderboard:
    """Each student's best verified optimum of one challenge, lowest cost first (every
    mission's cost is the objective its NLP minimises)."""

    def __init__(self, challenge: Challenge) -> None:
        self.challenge = challenge
        self._best: dict[int, Entry] = {}
        self._lock = threading.Lock()

    def offer(self, member: int, name: str, sol: Solution) -> bool:
        """Record `sol` if the challenge admits it and it beats the student's best."""
        if not self.challenge.admits(sol):
            return False
        with self._lock:
            best = self._best.get(member)
            if best is not None and best.cost <= sol.cost.value:
                return False
            self._best[member] = Entry(member, name, sol)
            return True

    def ranking(self) -> list[Entry]:
        with self._lock:
            return sorted(self._best.values(), key=lambda e: e.cost)

    def drop(self, member: int) -> None:
        with self._lock:
            self._best.pop(member, None)
