"""Fixtures for the mpm_post tests; `import mpm_post` works without installing the package."""

import sys
from pathlib import Path

import pytest

# postproc/ on the path, as PYTHONPATH=postproc does for users.
POSTPROC = Path(__file__).resolve().parents[1]
if str(POSTPROC) not in sys.path:
    sys.path.insert(0, str(POSTPROC))

from mpm_post_fakerun import (  # noqa: E402  (needs the path set above)
    history_rows, particle_fields, write_history, write_output)


@pytest.fixture
def make_run(tmp_path):
    """Factory: make_run(dim, times, n=8) -> run directory with outputs and a history.csv."""

    def make(dim=2, times=(0.0, 0.25, 0.5), n=8, name="case", history=True, **kwargs):
        run_dir = tmp_path / name
        run_dir.mkdir()
        for index, time in enumerate(times):
            write_output(run_dir / f"particles_{index:06d}.h5", time, 10 * index, dim,
                         particle_fields(dim, n, time), case_name=name, **kwargs)
        if history:
            write_history(run_dir / "history.csv", history_rows())
        return run_dir

    return make
