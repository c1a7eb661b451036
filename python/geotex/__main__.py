"""The geotex command line from Python: `python -m geotex ARGS` and the `geotex` command pip installs.

Both run the same CLI binary (built with the module by the project's CMake): the copy installed in the
package (geotex/bin/geotex), or, in a build tree (PYTHONPATH=build/python), the build's own build/geotex."""

import os
import sys
from pathlib import Path


def cli_path() -> Path:
    """The geotex CLI binary that belongs to this copy of the module."""
    here = Path(__file__).resolve().parent
    for candidate in (here / "bin" / "geotex", here.parent.parent / "geotex"):
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return candidate
    raise FileNotFoundError(f"the geotex command line is not installed beside {here} (reinstall with pip)")


def main() -> None:
    try:
        binary = cli_path()
    except FileNotFoundError as e:
        print(f"geotex: error: {e}", file=sys.stderr)
        raise SystemExit(1)
    sys.stdout.flush()
    sys.stderr.flush()
    # Replace this process: exit codes, signals and stdin/stdout behave exactly as the binary's own.
    os.execv(str(binary), ["geotex", *sys.argv[1:]])


if __name__ == "__main__":
    main()
