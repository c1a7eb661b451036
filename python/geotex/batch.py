"""Run a geotex operation over many meshes on a Dask distributed cluster.

    from geotex import batch
    result = batch.run("smooth", "scans/", output_dir="smoothed/", steps=3)
    print(result.table())

By default a local cluster of two single-threaded worker processes on 127.0.0.1 is started (and
stopped afterwards); pass ``scheduler="tcp://host:8786"`` to use a running cluster (its workers
need the geotex module importable). Every file is processed independently: an error in one file
(unreadable, non-manifold, solver failure, …) is recorded in its row and the batch goes on.
Inputs are never modified; outputs are written atomically into ``output_dir`` with the input's
name (and the operation's extension), and an input path is never used as an output.

Command line: ``python3 -m geotex.batch OPERATION INPUT… -o OUT_DIR [--scheduler ADDR]
[--workers N] [--set key=value …]``.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Union

MESH_EXTENSIONS = (".obj", ".ply", ".off", ".stl")


def _op_info(path: Path, out_dir: Optional[Path], **options) -> dict:
    import geotex

    V, F = geotex.read_mesh(str(path))
    return {"info": geotex.info(V, F)}


def _write(out_dir: Optional[Path], path: Path, V, F, suffix: str = "") -> Optional[str]:
    import geotex

    if out_dir is None:
        return None
    out = out_dir / (path.stem + suffix + path.suffix)
    if out.resolve() == path.resolve():
        raise geotex.InvalidInput(f"{out}: output would replace the input")
    geotex.write_mesh(str(out), V, F)
    return str(out)


def _op_smooth(path: Path, out_dir: Optional[Path], **options) -> dict:
    import geotex

    V, F = geotex.read_mesh(str(path))
    Vs = geotex.smooth(V, F, **options)
    return {"output": _write(out_dir, path, Vs, F), "vertices": int(V.shape[0]), "faces": int(F.shape[0])}


def _op_noise(path: Path, out_dir: Optional[Path], **options) -> dict:
    import geotex

    V, F = geotex.read_mesh(str(path))
    Vn = geotex.add_noise(V, F, **options)
    return {"output": _write(out_dir, path, Vn, F), "vertices": int(V.shape[0])}


def _op_denoise(path: Path, out_dir: Optional[Path], **options) -> dict:
    import geotex

    if not hasattr(geotex, "denoise"):
        raise RuntimeError("this geotex build has no denoise()")
    V, F = geotex.read_mesh(str(path))
    out = geotex.denoise(V, F, **options)
    V2, F2 = out["V"], out["F"]
    row = {"output": _write(out_dir, path, V2, F2), "faces": int(F2.shape[0])}
    if "edge_labels" in out and out["edge_labels"] is not None:
        row["sharp_edges"] = int((out["edge_labels"] > 0.5).sum())
    return row


#: Operations by name; each takes (input path, output folder or None, **options) and returns a dict.
OPERATIONS: Dict[str, Callable[..., dict]] = {
    "info": _op_info,
    "smooth": _op_smooth,
    "noise": _op_noise,
    "denoise": _op_denoise,
}


def _run_one(operation: Union[str, Callable[..., dict]], path: str, out_dir: Optional[str], options: dict) -> dict:
    """Runs on a worker. Never raises: errors become the row's 'error'."""
    t0 = time.perf_counter()
    row: Dict[str, Any] = {"file": path, "status": "ok", "error": None}
    try:
        fn = OPERATIONS[operation] if isinstance(operation, str) else operation
        row.update(fn(Path(path), Path(out_dir) if out_dir else None, **options) or {})
    except Exception as e:  # noqa: BLE001 - every failure is reported per file
        row["status"] = "error"
        row["error"] = f"{type(e).__name__}: {e}"
    row["seconds"] = round(time.perf_counter() - t0, 4)
    row["worker_pid"] = os.getpid()
    return row


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
        for r in sorted(self.rows, key=lambda r: r["file"]):
            detail = r["error"] if r["error"] else (r.get("output") or "")
            lines.append(f"{r['status']:6}  {r['seconds']:8.3f}  {r['file']}  {detail}")
        lines.append(f"{len(self.ok)} ok, {len(self.failed)} failed, {len(self.rows)} files, {self.seconds:.1f} s")
        return "\n".join(lines)


def collect_inputs(inputs: Union[str, os.PathLike, Iterable[Union[str, os.PathLike]]]) -> List[str]:
    """A folder (its mesh files, sorted), a single file, or a list of files."""
    if isinstance(inputs, (str, os.PathLike)):
        p = Path(inputs)
        if p.is_dir():
            return sorted(str(f) for f in p.iterdir() if f.suffix.lower() in MESH_EXTENSIONS and f.is_file())
        return [str(p)]
    return [str(Path(f)) for f in inputs]


def run(
    operation: Union[str, Callable[..., dict]],
    inputs,
    output_dir: Optional[Union[str, os.PathLike]] = None,
    scheduler: Optional[str] = None,
    n_workers: int = 2,
    threads_per_worker: int = 1,
    progress: bool = True,
    **options,
) -> BatchResult:
    """Run ``operation`` (a name in OPERATIONS or a picklable callable) on every input mesh.

    ``options`` are passed to the operation (the same keyword arguments as the geotex function,
    e.g. ``steps=3`` for smooth). Returns a BatchResult with one row per input, in input order.
    """
    from distributed import Client, LocalCluster, as_completed

    if isinstance(operation, str) and operation not in OPERATIONS:
        raise ValueError(f"unknown operation {operation!r}; choose from {sorted(OPERATIONS)}")
    files = collect_inputs(inputs)
    if output_dir is not None:
        Path(output_dir).mkdir(parents=True, exist_ok=True)
    out = str(output_dir) if output_dir is not None else None
    t0 = time.perf_counter()
    cluster = None
    if scheduler is None:
        cluster = LocalCluster(
            n_workers=n_workers,
            threads_per_worker=threads_per_worker,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
        )
    client = Client(cluster if cluster is not None else scheduler)
    try:
        futures = [client.submit(_run_one, operation, f, out, options, key=f"geotex-{i}-{Path(f).name}", pure=False)
                   for i, f in enumerate(files)]
        index = {fut.key: i for i, fut in enumerate(futures)}
        rows: List[Optional[dict]] = [None] * len(files)
        for done, fut in enumerate(as_completed(futures), start=1):
            i = index[fut.key]
            try:
                rows[i] = fut.result()
            except Exception as e:  # a worker died: record it, keep going
                rows[i] = {"file": files[i], "status": "error", "error": f"worker lost: {e}", "seconds": 0.0}
            if progress:
                r = rows[i] or {}
                print(f"[{done}/{len(files)}] {r['status']:5} {files[i]}" + (f": {r['error']}" if r["error"] else ""),
                      file=sys.stderr, flush=True)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return BatchResult(rows=[r for r in rows if r is not None], seconds=time.perf_counter() - t0)


def _parse_value(text: str):
    try:
        return json.loads(text)
    except ValueError:
        return text


def main(argv: Optional[Sequence[str]] = None) -> int:
    ap = argparse.ArgumentParser(prog="python3 -m geotex.batch", description=__doc__.split("\n\n")[0])
    ap.add_argument("operation", choices=sorted(OPERATIONS))
    ap.add_argument("inputs", nargs="+", help="mesh files or a folder")
    ap.add_argument("-o", "--output-dir", help="folder for the outputs (created)")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (default: a local cluster)")
    ap.add_argument("--workers", type=int, default=2, help="local cluster: number of worker processes")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="operation option (JSON value)")
    ap.add_argument("--json", help="also write the rows as JSON to this file")
    args = ap.parse_args(argv)
    options = {}
    for kv in args.set:
        if "=" not in kv:
            ap.error(f"--set expects KEY=VALUE, got {kv!r}")
        k, v = kv.split("=", 1)
        options[k] = _parse_value(v)
    inputs = args.inputs[0] if len(args.inputs) == 1 else args.inputs
    result = run(args.operation, inputs, args.output_dir, scheduler=args.scheduler, n_workers=args.workers, **options)
    print(result.table())
    if args.json:
        Path(args.json).write_text(json.dumps(result.rows, indent=2))
    return 0 if not result.failed else 1


if __name__ == "__main__":
    sys.exit(main())
