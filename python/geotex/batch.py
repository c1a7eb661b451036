"""Run a geotex operation over many meshes, in parallel, on this machine or on a cluster.

    from geotex import batch
    result = batch.run("smooth", "scans/", output_dir="smoothed/", steps=3)
    print(result.table())

The operations are the functions of the geotex module that take a mesh (``batch.operations()``:
smooth, denoise, add_noise, deform, parametrize, phong_project, texture_*, resize, render, …, with
the command line's names as aliases: noise, param, project), with the same keyword options. Every
option is checked before any file is read (names, types, ranges, choices, presets, missing arguments:
the checks the call itself makes); a bad one raises BatchOptionError listing every problem.

Where the work runs: ``executor=`` takes any ``concurrent.futures.Executor``; by default a
``ProcessPoolExecutor`` with ``workers`` processes (``workers=1``: in this process). A Dask cluster
(several machines) is used through its executor, ``distributed.Client("tcp://host:8786").get_executor()``
(docs/batch.md). The results do not depend on where a file ran: each is processed alone, by the same
function, with one thread per worker unless ``threads=`` says otherwise.

Every file is processed independently: an error in one file (unreadable, non-manifold, solver
failure, …) is recorded in its row and the batch goes on. Inputs are never modified; outputs are
written atomically into ``output_dir`` with the input's name: a mesh result with the input's
extension, other arrays in ``NAME.npz``, pictures and pages as ``NAME.png`` / ``NAME.html``; an input
path is never used as an output.

Command line: ``python3 -m geotex.batch OPERATION INPUT… -o OUT_DIR [--workers N] [--scheduler ADDR]
[--set key=value …] [--json ROWS.json]``. A value is JSON (``steps=3``, ``scale=[2,1,1]``) or a
string (``method=surfel``); ``@FILE`` loads an array (``.npy``) or a mesh (as its (V, F)), the same for
every input (``--set height=@h.npy``). Exit code 2 for a bad option (reported once, before any file is
read), 1 when some file failed, 0 otherwise.
"""

from __future__ import annotations

import argparse
import inspect
import json
import os
import sys
import tempfile
import time
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Tuple, Union

MESH_EXTENSIONS = (".obj", ".ply", ".off", ".stl")

#: The first parameter names that make a geotex function an operation on one input file: its mesh
#: (mesh, result), a base with the input's connectivity (V_base), the input's vertices as points (P),
#: a list of meshes (meshes), or a texture file (texture: read with read_texture()).
_INPUT_PARAMETERS = ("mesh", "result", "V_base", "P", "meshes", "texture")

#: Command-line names of operations whose function has another name.
ALIASES = {"noise": "add_noise", "param": "parametrize", "project": "phong_project"}

#: Arguments without which a function cannot run although their default is None (the function raises
#: TypeError without them). A test checks this list against the functions.
NEEDS = {
    "deform": ("handles", "targets"),
    "phong_project": ("P",),
    "one_form_fit": ("T",),
    "one_form_to_vertices": ("c",),
    "compare": ("V_truth",),
}

#: Output file suffix of functions that write a file themselves (their `path` argument).
_PATH_SUFFIX = {"render": ".png", "view": ".html"}


class BatchOptionError(ValueError):
    """An operation or option that cannot run; the message lists every problem, one per line."""


@dataclass(frozen=True)
class Operation:
    """A geotex function driven over files: how the input mesh is passed, what else it needs."""

    name: str             #: the function's name in the geotex module
    input: str            #: its first parameter (one of _INPUT_PARAMETERS)
    takes_faces: bool     #: the second parameter is F
    required: Tuple[str, ...]  #: arguments the options must give
    options_table: Optional[str]  #: the C++ options struct behind its keyword options, if any

    @property
    def function(self) -> Callable[..., Any]:
        import geotex

        return getattr(geotex, self.name)


def operations() -> Dict[str, Operation]:
    """Every geotex function that takes a mesh, by name (the functions of the module: a function added
    to geotex is an operation here without further work)."""
    import geotex

    ops: Dict[str, Operation] = {}
    for name in geotex.__all__:
        fn = getattr(geotex, name, None)
        if fn is None or not inspect.isfunction(fn):
            continue
        try:
            params = list(inspect.signature(fn).parameters.values())
        except (TypeError, ValueError):
            continue
        if not params or params[0].name not in _INPUT_PARAMETERS:
            continue
        takes_faces = len(params) > 1 and params[1].name == "F"
        filled = {params[0].name, "F" if takes_faces else None, "path" if name in _PATH_SUFFIX else None}
        required = tuple(p.name for p in params
                         if p.name not in filled and p.default is inspect.Parameter.empty
                         and p.kind not in (inspect.Parameter.VAR_KEYWORD, inspect.Parameter.VAR_POSITIONAL))
        required += tuple(n for n in NEEDS.get(name, ()) if n not in required)
        ops[name] = Operation(name, params[0].name, takes_faces, required, getattr(fn, "options_table", None))
    return ops


def operation_names() -> List[str]:
    """The names run() accepts: the functions, then the command-line aliases."""
    ops = operations()
    return sorted(ops) + sorted(a for a, n in ALIASES.items() if n in ops)


def _operation(name: str) -> Operation:
    ops = operations()
    op = ops.get(ALIASES.get(name, name)) or ops.get(name.replace("-", "_"))
    if op is None:
        raise BatchOptionError(f"unknown operation {name!r}; choose from {', '.join(operation_names())}")
    return op


def _type_problem(param: inspect.Parameter, value: Any) -> Optional[str]:
    """A type mismatch between a value and a plain keyword's default (the options of a table are
    checked by the library itself)."""
    default = param.default
    if value is None:
        return None
    if default is None or default is inspect.Parameter.empty:
        # Only the annotation tells: a text where it names no str, a number where it names a sequence.
        ann = param.annotation if isinstance(param.annotation, str) else getattr(param.annotation, "__name__", "")
        if not ann or "Any" in ann:
            return None
        if isinstance(value, str) and "str" not in ann and "Literal" not in ann and "PathLike" not in ann:
            return f"{param.name}={value!r}: expected {ann}"
        if isinstance(value, (int, float)) and not any(t in ann for t in ("int", "float", "bool")):
            return f"{param.name}={value!r}: expected {ann}"
        return None
    if isinstance(default, bool):
        ok = isinstance(value, bool)
    elif isinstance(default, (int, float)):
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        if ok and isinstance(default, int) and not isinstance(default, bool) and isinstance(value, float):
            ok = value.is_integer()
    elif isinstance(default, str):
        ok = isinstance(value, str) or not isinstance(value, (int, float, bool))  # a str or an array/sequence
    elif isinstance(default, (tuple, list)):
        ok = not isinstance(value, (str, bool, int, float))
    else:
        ok = True
    return None if ok else f"{param.name}={value!r}: expected a value like {default!r}"


def check_options(operation: str, options: Dict[str, Any]) -> Operation:
    """Check an operation and its options without running anything: unknown names, wrong types,
    values out of range, unknown choices or presets (by the library's own checks), missing arguments.
    Raises BatchOptionError naming every problem; returns the operation."""
    import geotex
    from geotex import _geotex

    op = _operation(operation)
    sig = inspect.signature(op.function)
    params = sig.parameters
    problems: List[str] = []
    fixed = {op.input, "F" if op.takes_faces else "", "path" if op.name in _PATH_SUFFIX else ""}
    forwards = any(p.kind == inspect.Parameter.VAR_KEYWORD for p in params.values())
    for key in options:
        if key in fixed:
            problems.append(f"{key}: set by the batch (the input file{' and its output' if key == 'path' else ''})")
        elif key not in params and not forwards:
            from geotex._options import closest_name

            options_of = [p for p in params if p not in fixed]
            close = [p for p in params if p.rstrip("_") == key.rstrip("_").replace("-", "_")]
            best = close[0] if close else closest_name(key.replace("-", "_"), options_of)
            hint = f" (did you mean {best}?)" if best else ""
            problems.append(f"{key}: not an option of {op.name}{hint}; its options: "
                            + ", ".join(p for p in params if p not in fixed))
    for name in op.required:
        if name not in options:
            problems.append(f"{name}: {op.name} needs it (--set {name}=…)")
    table_params = set()
    if op.options_table:
        from geotex._options import python_name, table

        table_params = {python_name(f["name"]) for f in table(op.options_table)["fields"]}
        table_params |= {"preset", "progress", "threads"}
        given = {k: v for k, v in options.items() if k in params and k in table_params}
        try:
            _geotex._check_options(op.options_table, given)
        except (ValueError, TypeError) as e:
            problems.append(str(e))
    for key, value in options.items():
        if key in params and key not in table_params:
            p = _type_problem(params[key], value)
            if p:
                problems.append(p)
    if forwards and not op.options_table and not problems:
        # A function passing its keywords on (denoise → the method's function): its options are known
        # only by calling it, so it is called once on a small generated sphere.
        V, F = geotex.generate("sphere", level=0)
        try:
            _process(op, Path("probe.ply"), None, {**options, **_thread_option(op)}, mesh=(V, F))
        except (TypeError, ValueError) as e:  # a wrong keyword, a value out of range (InvalidInput)
            problems.append(str(e))
        except Exception:  # noqa: BLE001 - not about the options: the files will tell
            pass
    if problems:
        raise BatchOptionError(f"{op.name}: " + ("\n  ".join(problems) if len(problems) == 1 else
                                                 "\n  " + "\n  ".join(problems)))
    return op


# ---------------------------------------------------------------------------------------------
# One file (runs on a worker)


def _atomic_write(path: Path, write: Callable[[str], None]) -> None:
    fd, tmp = tempfile.mkstemp(prefix="." + path.name + ".", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _output(out_dir: Path, path: Path, suffix: str) -> Path:
    import geotex

    out = out_dir / (path.stem + suffix)
    if out.resolve() == path.resolve():
        raise geotex.InvalidInput(f"{out}: output would replace the input")
    return out


def _summary(value: Any) -> Any:
    """A JSON-friendly account of a value for the row (arrays by their shape)."""
    import numpy as np

    if isinstance(value, np.ndarray):
        return value.item() if value.ndim == 0 else f"array{tuple(value.shape)}"
    if isinstance(value, (np.integer, np.floating, np.bool_)):
        return value.item()
    if isinstance(value, dict):
        return {str(k): _summary(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_summary(v) for v in value] if len(value) <= 16 else f"{type(value).__name__}[{len(value)}]"
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    if hasattr(value, "shape"):  # scipy.sparse
        return f"{type(value).__name__}{tuple(value.shape)}"
    return repr(value)


def _fields(value: Any, name: str) -> Dict[str, Any]:
    """The named parts of a result: a Result's or dict's fields, a tuple's items, or the value itself."""
    if hasattr(value, "keys") and callable(value.keys):
        return {k: value[k] for k in value.keys()}
    if isinstance(value, tuple):
        return {f"{name}{k}": v for k, v in enumerate(value)}
    return {name: value}


def _thread_option(op: Operation) -> Dict[str, Any]:
    """threads=1 for the functions that take it: one core per file, the workers are the parallelism
    (and a file's result does not depend on the number of cores where it ran)."""
    params = inspect.signature(op.function).parameters
    takes = "threads" in params or op.options_table or any(p.kind == inspect.Parameter.VAR_KEYWORD for p in params.values())
    return {"threads": 1} if takes else {}


def _process(op: Operation, path: Path, out_dir: Optional[Path], options: Dict[str, Any],
             mesh: Optional[Tuple[Any, Any]] = None) -> dict:
    import numpy as np

    import geotex

    args: Dict[str, Any] = dict(options)
    if op.input == "texture":
        texture = geotex.read_texture(str(path))
        V, F = texture.V_base, texture.F
        args["texture"] = texture
    else:
        V, F = mesh if mesh is not None else geotex.read_mesh(str(path))
    if op.input == "texture":
        pass  # passed above
    elif op.input == "meshes":
        args["meshes"] = [{"name": path.name, "V": V, "F": F}]
    elif op.input == "P":
        args["P"] = V
    else:
        args[op.input] = V
    if op.takes_faces:
        args["F"] = F
    row: Dict[str, Any] = {"vertices": int(V.shape[0]), "faces": int(F.shape[0])}
    if op.name in _PATH_SUFFIX:
        if out_dir is None:  # nothing to keep: the file goes to a temporary folder
            with tempfile.TemporaryDirectory() as tmp:
                op.function(**{**args, "path": str(Path(tmp) / ("out" + _PATH_SUFFIX[op.name]))})
            return row
        else:
            out = _output(out_dir, path, _PATH_SUFFIX[op.name])
            _atomic_write(out, lambda tmp: op.function(**{**args, "path": tmp}))
            row["output"] = str(out)
            return row
    value = op.function(**args)
    parts = _fields(value, "value")
    # A mesh result: positions of the input's vertices (the same faces), or a Result with V and F.
    result_mesh: Optional[Tuple[Any, Any]] = None
    # A texture result (texture_extract, texture_edit; transfer, atlas and synthesize nest one): a texture file.
    texture_out = value if all(k in parts for k in ("V_base", "F", "height", "tilt")) else parts.pop("texture", None)
    if texture_out is value:
        parts = {k: v for k, v in parts.items() if k not in ("V_base", "F", "height", "tilt", "lean", "edges")}
    if isinstance(value, np.ndarray) and value.ndim == 2 and value.shape == V.shape and value.dtype.kind == "f":
        result_mesh, parts = (value, F), {}
    elif "V" in parts and "F" in parts:
        result_mesh = (parts.pop("V"), parts.pop("F"))
    elif "V" in parts and isinstance(parts["V"], np.ndarray) and parts["V"].shape == V.shape:
        result_mesh = (parts.pop("V"), F)
    arrays = {k: v for k, v in parts.items() if isinstance(v, np.ndarray) and v.ndim > 0}
    sparse = {k: v for k, v in parts.items() if hasattr(v, "tocsr") and hasattr(v, "shape")}
    row["result"] = {k: _summary(v) for k, v in parts.items() if k not in arrays and k not in sparse}
    if not row["result"]:
        del row["result"]
    if out_dir is not None:
        if texture_out is not None:
            out = _output(out_dir, path, ".texture.ply")
            _atomic_write(out, lambda tmp: geotex.write_texture(tmp, texture_out))
            row["texture"] = str(out)
        if result_mesh is not None:
            out = _output(out_dir, path, path.suffix)
            Vo, Fo = result_mesh
            _atomic_write(out, lambda tmp: geotex.write_mesh(tmp, Vo, Fo))
            row["output"] = str(out)
        if arrays or sparse:
            out = _output(out_dir, path, ".npz")
            if sparse:
                arrays.update({f"{k}_{a}": getattr(m.tocoo(), a) for k, m in sparse.items() for a in ("row", "col", "data")})
                arrays.update({f"{k}_shape": np.asarray(m.shape) for k, m in sparse.items()})
            _atomic_write(out, lambda tmp: np.savez(tmp, **arrays))
            row["arrays"] = str(out)
    for k, v in arrays.items():
        row.setdefault("shapes", {})[k] = list(v.shape)
    return row


def _run_one(operation: str, path: str, out_dir: Optional[str], options: dict) -> dict:
    """Runs on a worker. Never raises: errors become the row's 'error'."""
    t0 = time.perf_counter()
    row: Dict[str, Any] = {"file": path, "status": "ok", "error": None}
    try:
        op = _operation(operation)
        row.update(_process(op, Path(path), Path(out_dir) if out_dir else None, options))
    except Exception as e:  # noqa: BLE001 - every failure is reported per file
        row["status"] = "error"
        row["error"] = f"{type(e).__name__}: {e}"
    row["seconds"] = round(time.perf_counter() - t0, 4)
    row["worker_pid"] = os.getpid()
    return row


# ---------------------------------------------------------------------------------------------
# Many files


@dataclass
class BatchResult:
    rows: List[dict] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def ok(self) -> List[dict]:
        return [r for r in self.rows if r["status"] == "ok"]

    @property
    def failed(self) -> List[dict]:
        return [r for r in self.rows if r["status"] != "ok"]

    def table(self) -> str:
        """A plain-text summary table: one row per file, then totals."""
        lines = [f"{'status':6}  {'seconds':>8}  file / error"]
        for r in self.rows:
            detail = r["error"] if r["error"] else (r.get("output") or r.get("arrays") or json.dumps(r.get("result", "")))
            lines.append(f"{r['status']:6}  {r['seconds']:8.3f}  {r['file']}  {detail}")
        lines.append(f"{len(self.ok)} ok, {len(self.failed)} failed, {len(self.rows)} files, {self.seconds:.1f} s")
        return "\n".join(lines)


def collect_inputs(inputs: Union[str, os.PathLike, Iterable[Union[str, os.PathLike]]]) -> List[str]:
    """A folder (its mesh files, sorted), a single file, or a list of files and folders."""
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    files: List[str] = []
    for item in inputs:
        p = Path(item)
        if p.is_dir():
            files += sorted(str(f) for f in p.iterdir() if f.suffix.lower() in MESH_EXTENSIONS and f.is_file())
        else:
            files.append(str(p))
    return files


def _worker_init(threads: int) -> None:
    os.environ["OMP_NUM_THREADS"] = str(threads)


def run(
    operation: str,
    inputs: Union[str, os.PathLike, Iterable[Union[str, os.PathLike]]],
    output_dir: Optional[Union[str, os.PathLike]] = None,
    *,
    executor: Optional[Executor] = None,
    workers: int = 2,
    progress: bool = True,
    **options: Any,
) -> BatchResult:
    """Run ``operation`` (see operations(); aliases noise, param, project) on every input mesh.

    ``options`` are the function's keyword arguments (``steps=3`` for smooth). They are all checked
    first (BatchOptionError). ``executor``: any concurrent.futures.Executor, e.g. a Dask client's
    ``get_executor()``; by default a process pool of ``workers`` processes, or this process when
    ``workers`` is 1. Returns a BatchResult with one row per input, in input order.
    """
    op = check_options(operation, options)
    files = collect_inputs(inputs)
    if output_dir is not None:
        Path(output_dir).mkdir(parents=True, exist_ok=True)
    out = str(output_dir) if output_dir is not None else None
    options = {**_thread_option(op), **options}
    t0 = time.perf_counter()
    rows: List[Optional[dict]] = [None] * len(files)

    def report(i: int, done: int) -> None:
        if progress:
            r = rows[i] or {}
            print(f"[{done}/{len(files)}] {r['status']:5} {files[i]}" + (f": {r['error']}" if r["error"] else ""),
                  file=sys.stderr, flush=True)

    if executor is None and workers <= 1:
        for i, f in enumerate(files):
            rows[i] = _run_one(op.name, f, out, options)
            report(i, i + 1)
    else:
        import concurrent.futures as cf
        import multiprocessing

        own = executor is None
        # spawn: a forked child of a process that has used OpenMP can hang in libgomp
        ex: Executor = executor if executor is not None else ProcessPoolExecutor(
            max_workers=workers, mp_context=multiprocessing.get_context("spawn"), initializer=_worker_init, initargs=(1,))
        try:
            futures = {ex.submit(_run_one, op.name, f, out, options): i for i, f in enumerate(files)}
            for done, fut in enumerate(cf.as_completed(futures), start=1):
                i = futures[fut]
                try:
                    rows[i] = fut.result()
                except Exception as e:  # the worker died: record it, keep going
                    rows[i] = {"file": files[i], "status": "error", "error": f"worker lost: {type(e).__name__}: {e}",
                               "seconds": 0.0}
                report(i, done)
        finally:
            if own:
                ex.shutdown()
    return BatchResult(rows=[r for r in rows if r is not None], seconds=time.perf_counter() - t0)


# ---------------------------------------------------------------------------------------------
# Command line


def parse_value(text: str) -> Any:
    """A --set value: @FILE (a .npy array or a mesh as (V, F)), JSON, or the text itself."""
    if text.startswith("@"):
        p = Path(text[1:])
        if not p.is_file():
            raise BatchOptionError(f"{p}: no such file")
        if p.suffix.lower() == ".npy":
            import numpy as np

            return np.load(p)
        if p.suffix.lower() in MESH_EXTENSIONS:
            import geotex

            return geotex.read_mesh(str(p))
        raise BatchOptionError(f"{p}: expected a .npy array or a mesh file")
    try:
        return json.loads(text)
    except ValueError:
        return text


#: seconds the command line waits for a Dask scheduler before it gives up
SCHEDULER_TIMEOUT = 3.0


def main(argv: Optional[Sequence[str]] = None) -> int:
    ap = argparse.ArgumentParser(prog="python3 -m geotex.batch", description=__doc__.split("\n\n")[0])
    ap.add_argument("operation", help="a geotex function taking a mesh (e.g. smooth, denoise, noise, resize, render)")
    ap.add_argument("inputs", nargs="+", help="mesh files or folders")
    ap.add_argument("-o", "--output-dir", help="folder for the outputs (created)")
    ap.add_argument("--workers", type=int, default=2, help="local worker processes (1: this process)")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://host:8786; needs dask.distributed)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="an option (JSON, text or @FILE)")
    ap.add_argument("--json", help="also write the rows as JSON to this file")
    args = ap.parse_args(argv)
    try:
        options: Dict[str, Any] = {}
        problems = []
        for kv in args.set:
            if "=" not in kv:
                problems.append(f"--set expects KEY=VALUE, got {kv!r}")
                continue
            k, v = kv.split("=", 1)
            try:
                options[k.strip()] = parse_value(v)
            except BatchOptionError as e:
                problems.append(f"{k}: {e}")
        if problems:
            raise BatchOptionError("\n  ".join(problems))
        check_options(args.operation, options)
    except BatchOptionError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    executor = None
    client = None
    if args.scheduler:
        try:
            from distributed import Client  # type: ignore[import-not-found]
        except ImportError:
            print("error: --scheduler needs dask.distributed (pip install distributed)", file=sys.stderr)
            return 2
        try:
            # One line within seconds for a scheduler that is not there (Dask's default waits 30 s
            # and prints its traceback).
            import dask  # type: ignore[import-not-found]

            with dask.config.set({"distributed.comm.timeouts.connect": f"{SCHEDULER_TIMEOUT}s"}):
                client = Client(args.scheduler, timeout=SCHEDULER_TIMEOUT)
        except Exception as e:  # noqa: BLE001 - OSError, TimeoutError, CommClosedError: all say the same
            print(f"error: cannot reach the Dask scheduler at {args.scheduler} within {SCHEDULER_TIMEOUT:g} s "
                  f"({type(e).__name__}: {str(e).splitlines()[0] if str(e) else 'no answer'})", file=sys.stderr)
            return 1
        executor = client.get_executor()
    try:
        result = run(args.operation, args.inputs, args.output_dir, executor=executor, workers=args.workers, **options)
    finally:
        if client is not None:
            client.close()
    print(result.table())
    if args.json:
        Path(args.json).write_text(json.dumps(result.rows, indent=2))
    return 0 if not result.failed else 1


if __name__ == "__main__":
    sys.exit(main())
