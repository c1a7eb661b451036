"""Write the type stubs of the geotex package (__init__.pyi) from the live signatures, which come from
the option tables: `python3 -m geotex._stubgen OUT_DIR`. Run at build time; checked by a test
(mypy's stubtest against the module)."""

from __future__ import annotations

import inspect
import sys
from pathlib import Path

HEADER = '''"""Type stubs of geotex, generated from the option tables by geotex._stubgen."""

import os
from typing import Any, Callable, Dict, List, Literal, Optional, Sequence, Tuple, Union

import numpy as np

from ._geotex import Error as Error, InvalidInput as InvalidInput, IoError as IoError, SolverError as SolverError

__version__: str
__all__: List[str]

MeshLike = Any
TextureLike = Any
_RESULT_CLASSES: Dict[str, Tuple[str, Tuple[str, ...]]]

class Result:
    def __init__(self, **fields: Any) -> None: ...
    def __getitem__(self, key: str) -> Any: ...
    def __contains__(self, key: object) -> bool: ...
    def keys(self) -> List[str]: ...
    def __getattr__(self, name: str) -> Any: ...

class MeshResult(Result):
    V: np.ndarray
    F: np.ndarray

class DenoiseResult(MeshResult):
    edges: np.ndarray
    edge_labels: np.ndarray
    parameters: Dict[str, Any]

class TextureResult(Result):
    V_base: np.ndarray
    F: np.ndarray
    height: np.ndarray
    tilt: np.ndarray
    lean: np.ndarray
    edges: np.ndarray

class TexturedResult(MeshResult):
    texture: TextureResult
    parameters: Dict[str, Any]
'''

# Python's type of a result field of each kind (geotex/core/results.h).
_RESULT_TYPES = {"bool": "bool", "int": "int", "float": "float", "str": "str", "texts": "List[str]",
                 "reals": "List[float]", "ints": "List[int]", "array": "np.ndarray", "record": "Dict[str, Any]",
                 "int_array": "np.ndarray"}


def _field_type(f: dict) -> str:
    t = _RESULT_TYPES[f["kind"]]
    return f"Optional[{t}]" if f["optional"] else t


def result_classes() -> str:
    """The typed result classes, from the C++ result tables (the ones the CLI's --report is written from)."""
    from . import _RESULT_CLASSES, _geotex
    tables = _geotex._result_tables()
    out = []
    for name, (base, parts) in _RESULT_CLASSES.items():
        fields = "".join(f"    {f['name']}: {_field_type(f)}\n" for t in parts for f in tables[t])
        out.append(f"\nclass {name}({base}):\n{fields}    parameters: Dict[str, Any]\n")
    return "".join(out) + "\n"


def results_markdown() -> str:
    """docs/results.md: every result table as the CLI's --report and Python show it (the docs' tables,
    from the same C++ tables as the report, the result classes and the demo's captions)."""
    from . import _RESULT_CLASSES, _geotex
    tables = _geotex._result_tables()
    out = ["# Results: every field a command reports\n\n",
           "Generated from the C++ result tables (`core/results.h`) by `PYTHONPATH=build/python /usr/bin/python3 -m ",
           "geotex._stubgen --results-md docs/results.md`; `python/tests/package/test_results.py` checks it is current. ",
           "A field's name is its `--report` key, its Python attribute and its name in the demo's captions. ",
           "Python only: per-vertex arrays the CLI writes as files, and older spellings.\n\n",
           "Python's result classes and the tables they hold:\n\n"]
    for name, (base, parts) in _RESULT_CLASSES.items():
        out.append(f"- `{name}` ({base}): " + ", ".join(f"[{t}](#{t.lower()})" for t in parts) + "\n")
    for t in sorted(tables):
        out.append(f"\n## {t}\n\n| field | type | unit | in --report | meaning |\n|---|---|---|---|---|\n")
        for f in tables[t]:
            report = "yes" if f["in_report"] else "Python only"
            help_text = f["help"].replace("|", "\\|")
            out.append(f"| `{f['name']}` | {_field_type(f)} | {f['unit']} | {report} | {help_text} |\n")
    return "".join(out)


# The compiled module: its errors, and everything else reached through the package's wrappers.
CORE = '''"""Type stubs of geotex._geotex (the compiled core; use the functions of the geotex package)."""

from typing import Any

class Error(RuntimeError): ...
class InvalidInput(ValueError): ...
class IoError(OSError): ...
class SolverError(Error): ...

def __getattr__(name: str) -> Any: ...
'''


def _annotation(a: object) -> str:
    if a is inspect.Parameter.empty:
        return "Any"
    if isinstance(a, str):
        return a
    return getattr(a, "__name__", repr(a))


def _default(v: object) -> str:
    # Stubs give defaults as `...` except for simple literals, which document the value.
    if v is None or isinstance(v, (bool, int, float, str)) and not (isinstance(v, float) and v != v):
        return repr(v)
    if isinstance(v, tuple) and all(isinstance(x, (int, float)) for x in v):
        return repr(v)
    return "..."


def stub_for(name: str, fn: object) -> str:
    sig = inspect.signature(fn)  # type: ignore[arg-type]
    parts = []
    star_done = False
    for p in sig.parameters.values():
        if p.kind == inspect.Parameter.KEYWORD_ONLY and not star_done:
            parts.append("*")
            star_done = True
        if p.kind == inspect.Parameter.VAR_KEYWORD:
            parts.append(f"**{p.name}: Any")
            continue
        if p.kind == inspect.Parameter.VAR_POSITIONAL:
            parts.append(f"*{p.name}: Any")
            star_done = True
            continue
        text = f"{p.name}: {_annotation(p.annotation)}"
        if p.default is not inspect.Parameter.empty:
            text += f" = {_default(p.default)}"
        parts.append(text)
    ret = _annotation(sig.return_annotation)
    return f"def {name}({', '.join(parts)}) -> {ret}: ...\n"


def generate() -> str:
    import geotex

    out = [HEADER, result_classes()]
    for name in geotex.__all__:
        obj = getattr(geotex, name)
        if inspect.isclass(obj):
            continue
        out.append(stub_for(name, obj))
    return "".join(out)


def main(argv: list) -> int:
    if len(argv) == 3 and argv[1] == "--results-md":
        Path(argv[2]).write_text(results_markdown())
        return 0
    if len(argv) != 2:
        print("usage: python3 -m geotex._stubgen OUT_DIR | --results-md FILE", file=sys.stderr)
        return 2
    out_dir = Path(argv[1])
    text = generate()
    target = out_dir / "__init__.pyi"
    if not target.exists() or target.read_text() != text:
        target.write_text(text)
    core = out_dir / "_geotex.pyi"
    if not core.exists() or core.read_text() != CORE:
        core.write_text(CORE)
    (out_dir / "py.typed").touch()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
