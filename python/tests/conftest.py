import os
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def data_dir():
    d = os.environ.get("GEOTEX_DATA", str(Path(__file__).resolve().parents[3] / "shared" / "data"))
    if not Path(d, "fandisk.obj").exists():
        pytest.skip("shared test data not found (expected ../shared/data beside the repo)")
    return Path(d)
