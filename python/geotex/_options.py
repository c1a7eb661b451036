"""Signatures from the option tables: every function whose behaviour is set by an options struct gets
one keyword-only argument per option, with the same name, default and range as the command line
(`geotex <command> --help`), from the one description in the C++ library."""

from __future__ import annotations

import functools
import inspect
import keyword
from typing import Any, Callable, Dict, List, Optional, Tuple

from . import _geotex

_TABLES: Dict[str, dict] = _geotex._option_tables()

# Arguments every option-taking call accepts besides its options.
CALL_ARGUMENTS = ("preset", "progress", "threads")

_KIND_TYPES = {"bool": "bool", "int": "int", "float": "float", "str": "str", "choice": "str",
               "vec3": "Tuple[float, float, float]"}


def python_name(name: str) -> str:
    """The keyword for option `name` (a Python keyword gets a trailing underscore: lambda_)."""
    return name + "_" if keyword.iskeyword(name) else name


def table(name: str) -> dict:
    """The description of options struct `name`: {"fields": [...], "presets": {...}}."""
    return _TABLES[name]


def annotation(field: dict) -> str:
    t = _KIND_TYPES[field["kind"]]
    if field["kind"] == "choice":
        t = "Literal[" + ", ".join(repr(c) for c in field["choices"]) + "]"
    return f"Optional[{t}]" if field["automatic"] else t


def _range(field: dict) -> str:
    lo, hi = field["lo"], field["hi"]
    if field["kind"] not in ("int", "float", "vec3"):
        return ""
    big = 2.0 ** 31 - 1
    has_lo, has_hi = lo > -big and lo == lo, hi < big and hi == hi
    fmt = lambda v: repr(int(v)) if float(v).is_integer() else repr(v)
    if has_lo and has_hi:
        return f"in {'(' if field['lo_open'] else '['}{fmt(lo)}, {fmt(hi)}{')' if field['hi_open'] else ']'}"
    if has_lo:
        return f"{'>' if field['lo_open'] else '>='} {fmt(lo)}"
    if has_hi:
        return f"{'<' if field['hi_open'] else '<='} {fmt(hi)}"
    return ""


def options_doc(names: List[str]) -> str:
    """An 'Options' section for a docstring, from the tables `names`."""
    lines = ["", "Options (keyword-only; the defaults are those of the command line):"]
    seen = set()
    for n in names:
        for f in _TABLES[n]["fields"]:
            if f["name"] in seen:
                continue
            seen.add(f["name"])
            extra = [x for x in (_range(f), f["ref"]) if x]
            if f["kind"] == "choice":
                extra.insert(0, "|".join(f["choices"]))
            default = "None (automatic)" if f["automatic"] and f["default"] is None else repr(f["default"])
            lines.append(f"    {python_name(f['name'])} = {default}: {f['help']}" + (f" ({'; '.join(extra)})" if extra else ""))
        presets = _TABLES[n]["presets"]
        if presets:
            lines.append("    preset = None: " + "; ".join(f"{k!r}: {v}" for k, v in presets.items()))
    lines.append("    progress = None: a callable(fraction, stage) called as the computation goes on")
    lines.append("    threads = None: number of threads for this call (default: all cores)")
    return "\n".join(lines) + "\n"


def _edit_distance(a: str, b: str) -> int:
    """Optimal string alignment distance (Levenshtein with adjacent transpositions), as the CLI's."""
    d = [[i + j if i * j == 0 else 0 for j in range(len(b) + 1)] for i in range(len(a) + 1)]
    for i in range(1, len(a) + 1):
        for j in range(1, len(b) + 1):
            d[i][j] = min(d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1]))
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                d[i][j] = min(d[i][j], d[i - 2][j - 2] + 1)
    return d[len(a)][len(b)]


def closest_name(name: str, candidates: List[str]) -> Optional[str]:
    """The candidate closest to `name`, or None when none is within a slip of it (a third of its
    letters, at least one and at most three: the rule of the command line's "did you mean")."""
    limit = min(max(len(name) // 3, 1), 3)
    best, best_distance = None, limit + 1
    for c in candidates:
        d = _edit_distance(name, c.rstrip("_"))  # lambda_ is 'lambda' spelt as a keyword allows
        if d < best_distance:
            best, best_distance = c, d
    return best


def _unexpected_keyword(fn: Callable, sig: inspect.Signature, kwargs: Dict[str, Any]) -> Optional[TypeError]:
    """TypeError naming the first keyword `sig` does not take, with the closest one it takes."""
    keywords = [p.name for p in sig.parameters.values()
                if p.kind in (inspect.Parameter.KEYWORD_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)]
    for name in kwargs:
        if name not in sig.parameters:
            best = closest_name(name, keywords)
            hint = f" (did you mean '{best}'?)" if best else ""
            return TypeError(f"{fn.__name__}() got an unexpected keyword argument '{name}'{hint}")
    return None


def with_options(table_name: str) -> Callable:
    """Give `fn(…, **options)` the options of table `table_name` as keyword-only arguments with their
    defaults. The wrapper passes on only the options given (the library applies the defaults and the
    preset); an unknown keyword raises TypeError, as for any Python function."""
    spec = _TABLES[table_name]

    def decorate(fn: Callable) -> Callable:
        own = [p for p in inspect.signature(fn).parameters.values() if p.kind != inspect.Parameter.VAR_KEYWORD]
        own_names = {p.name for p in own}
        params = list(own)
        for f in spec["fields"]:
            name = python_name(f["name"])
            if name in own_names:
                continue
            params.append(inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=f["default"],
                                            annotation=annotation(f)))
        if spec["presets"]:
            params.append(inspect.Parameter("preset", inspect.Parameter.KEYWORD_ONLY, default=None,
                                            annotation="Optional[str]"))
        params.append(inspect.Parameter("progress", inspect.Parameter.KEYWORD_ONLY, default=None,
                                        annotation="Optional[Callable[[float, str], None]]"))
        params.append(inspect.Parameter("threads", inspect.Parameter.KEYWORD_ONLY, default=None,
                                        annotation="Optional[int]"))
        sig = inspect.Signature(params, return_annotation=inspect.signature(fn).return_annotation)

        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            try:
                bound = sig.bind(*args, **kwargs)
            except TypeError as e:
                unexpected = _unexpected_keyword(fn, sig, kwargs)
                if unexpected is None:
                    raise
                raise unexpected from None
            positional = {k: v for k, v in bound.arguments.items() if k in own_names}
            options = {k: v for k, v in bound.arguments.items() if k not in own_names}
            return fn(**positional, **options)

        wrapper.__signature__ = sig  # type: ignore[attr-defined]
        wrapper.__doc__ = (fn.__doc__ or "").rstrip() + "\n" + options_doc([table_name])
        wrapper.options_table = table_name  # type: ignore[attr-defined]
        return wrapper

    return decorate
