#!/usr/bin/python3
"""The library's layers (docs/architecture.md): a layer uses only the layers above it in this list.

Every `#include "geotex/<layer>/..."` in include/geotex/<layer>/ and src/<layer>/ must name the file's own
layer or one above it; the test prints each include that goes down the list and fails if there is one.
Usage: check_layers.py [REPO]   (default: the repository this file is in)
"""

import pathlib
import re
import sys

LAYERS = ["core", "toolkit", "denoise", "texture", "resize", "tools"]  # top first
# Known breaks, (file, "layer/header") pairs, listed so that no new one comes in: none.
KNOWN = set()
INCLUDE = re.compile(r'^\s*#\s*include\s+"geotex/([a-z_]+)/([^"]+)"', re.M)


def violations(repo):
    out = []
    for root in ("include/geotex", "src"):
        for layer in LAYERS:
            for path in sorted((repo / root / layer).glob("*")):
                if path.suffix not in (".h", ".cpp", ".inc"):
                    continue
                for m in INCLUDE.finditer(path.read_text(errors="replace")):
                    used = m.group(1)
                    rel = str(path.relative_to(repo))
                    if (rel, f"{used}/{m.group(2)}") in KNOWN:
                        continue
                    if used in LAYERS and LAYERS.index(used) > LAYERS.index(layer):
                        out.append(f"{path.relative_to(repo)}: {layer} includes geotex/{used}/{m.group(2)}, a layer below it")
    return out


def main():
    repo = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    if not (repo / "include/geotex/core").is_dir():
        print(f"{repo}: no include/geotex/core here", file=sys.stderr)
        return 2
    bad = violations(repo)
    for line in bad:
        print(line)
    print(f"{len(bad)} include(s) going down the layers {' > '.join(LAYERS)} ({len(KNOWN)} known, listed in KNOWN)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
