"""Find the line of a mistake in a mission file from its source: the keyword or dictionary
key of a call (from the AST), the bracket a syntax error left open (from the tokens), the
`math`/`numpy` function a user's function calls. Each returns None when it cannot tell, and the
caller keeps the line it had."""

from __future__ import annotations

import ast
import dis
import io
import tokenize
import types
from collections.abc import Callable
from pathlib import Path
from typing import Any

NUMERIC_MODULES = ("math", "numpy", "cmath")


def _calls_at(path: Path, line: int) -> list[ast.Call]:
    """The calls of the file whose source spans `line`, innermost first."""
    try:
        tree = ast.parse(path.read_text(encoding="utf-8"))
    except (OSError, SyntaxError, ValueError):
        return []
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call)
             and n.lineno <= line <= (n.end_lineno or n.lineno)]
    return sorted(calls, key=lambda n: (n.end_lineno or n.lineno) - n.lineno)


def keyword_line(path: Path, line: int, name: str) -> int | None:
    """The line of keyword argument `name=` of the call spanning `line`."""
    for call in _calls_at(path, line):
        for kw in call.keywords:
            if kw.arg == name:
                return kw.value.lineno if kw.lineno is None else kw.lineno
    return None


def dict_key_line(path: Path, line: int, name: str, key: str) -> int | None:
    """The line of `key` in the dictionary literal given as `name=` to the call spanning
    `line` (e.g. a `tolerances={...}` entry); else the line of `name=` itself."""
    for call in _calls_at(path, line):
        for kw in call.keywords:
            if kw.arg != name:
                continue
            if isinstance(kw.value, ast.Dict):
                for k in kw.value.keys:
                    if isinstance(k, ast.Constant) and k.value == key:
                        return k.lineno
            return kw.lineno
    return None


def unclosed_bracket_line(text: str) -> int | None:
    """The line of the bracket that a "'(' was never closed" error really left open.

    Python names the outermost bracket (the `UserMission(` line) because a later `)` closes
    the inner one. The inner one is found where the next argument of an outer bracket
    starts, at that bracket's argument indentation, while brackets opened inside it on
    earlier lines are still open."""
    stack: list[list[Any]] = []  # [char, line, argument column or None]
    line_start = True
    try:
        for tok in tokenize.generate_tokens(io.StringIO(text).readline):
            if tok.type in (tokenize.NL, tokenize.NEWLINE):
                line_start = True
                continue
            if tok.type in (tokenize.COMMENT, tokenize.INDENT, tokenize.DEDENT):
                continue
            if line_start and stack and tok.string not in ")]}":
                col = tok.start[1]
                if stack[-1][2] is None:
                    stack[-1][2] = col
                for i, entry in enumerate(stack[:-1]):
                    if entry[2] == col and stack[i + 1][1] < tok.start[0]:
                        return int(stack[-1][1])
            line_start = False
            if tok.type == tokenize.OP and tok.string in "([{":
                stack.append([tok.string, tok.start[0], None])
            elif tok.type == tokenize.OP and tok.string in ")]}" and stack:
                stack.pop()
    except (tokenize.TokenError, IndentationError, SyntaxError):
        pass
    return None


def _tokens(text: str) -> list[tokenize.TokenInfo]:
    """The file's significant tokens, as far as the tokenizer gets."""
    out: list[tokenize.TokenInfo] = []
    skip = (tokenize.NL, tokenize.NEWLINE, tokenize.COMMENT, tokenize.INDENT, tokenize.DEDENT)
    try:
        for tok in tokenize.generate_tokens(io.StringIO(text).readline):
            if tok.type not in skip:
                out.append(tok)
    except (tokenize.TokenError, IndentationError, SyntaxError):
        pass
    return out


def positional_after_keyword_line(text: str, line: int) -> int | None:
    """The line of the first positional argument after a keyword argument in the call that
    a "positional argument follows keyword argument" error reports at `line` (Python names
    the call's closing bracket)."""
    toks = _tokens(text)
    # [index of the bracket, saw a keyword, answer, inside a lambda's parameters]
    stack: list[list[Any]] = []
    for k, tok in enumerate(toks):
        if stack and tok.string in ("lambda", ":"):
            stack[-1][3] = tok.string == "lambda"
        if stack and not stack[-1][3] and toks[k - 1].string in ("(", ","):
            entry = stack[-1]
            is_keyword = tok.type == tokenize.NAME and k + 1 < len(toks) \
                and toks[k + 1].string == "="
            if is_keyword or tok.string == "**":
                entry[1] = True
            elif entry[1] and entry[2] is None and tok.string not in ("*", ")"):
                entry[2] = tok.start[0]
        if tok.string in "([{" and tok.type == tokenize.OP:
            stack.append([k, False, None, False])
        elif tok.string in ")]}" and tok.type == tokenize.OP and stack:
            entry = stack.pop()
            if tok.start[0] == line and entry[2] is not None:
                return int(entry[2])
    return None


def numeric_call_line(fn: Callable[..., Any]) -> tuple[int, str] | None:
    """(line, 'math.exp') of the first use of a `math`/`numpy` function in `fn`'s code (as
    `math.exp`, `np.exp` or an imported `exp`), from its bytecode and globals."""
    code = getattr(fn, "__code__", None)
    if code is None:
        return None
    scope = getattr(fn, "__globals__", {})
    instructions = list(dis.get_instructions(code))
    for k, ins in enumerate(instructions):
        if ins.opname not in ("LOAD_GLOBAL", "LOAD_DEREF", "LOAD_NAME"):
            continue
        value = scope.get(str(ins.argval))
        line = ins.positions.lineno if ins.positions else None
        if isinstance(value, types.ModuleType) and value.__name__ in NUMERIC_MODULES:
            after = instructions[k + 1] if k + 1 < len(instructions) else None
            if after is not None and after.opname in ("LOAD_ATTR", "LOAD_METHOD") and line:
                return line, f"{ins.argval}.{after.argval}"
        module = getattr(value, "__module__", None) or ""
        if callable(value) and module.split(".")[0] in NUMERIC_MODULES and line:
            return line, f"{module.split('.')[0]}.{ins.argval}"
    return None
