"""An HDF5 particle list (bodies[i].particle_list = a .h5 file): the particles of a run's
output start a new case."""

import os
import re
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
EXE = REPO / "build" / "mpm_geo"

CASE = ('{{"name": "{name}", "domain": {{"nx": 8, "ny": 6, "dx": 0.1}}, "particles": {{"ppc": 2}}, '
        '"materials": [{{"name": "soil", "type": "linear_elastic", "E": 1e6, "nu": 0.3, '
        '"rho": 2000}}, {{"name": "rock", "type": "linear_elastic", "E": 1e7, "nu": 0.3, '
        '"rho": 2500}}], "bodies": [{body}], "gravity": [0, -9.81], '
        '"time": {{"tend": {tend}}}, "output": {{"interval": {tend}, "fields": ["position", "volume", '
        '"stress", "material"]}}}}')


def exe():
    if not EXE.exists():
        if os.environ.get("MPM_STRICT_TESTS") == "1":
            pytest.fail(f"{EXE} is missing (make build)")
        pytest.skip(f"{EXE} is missing (make build)")
    return str(EXE)


def run(case, *args):
    return subprocess.run([exe(), str(case), *args], capture_output=True, text=True,
                          check=False)


def test_the_particles_of_an_output_start_a_new_case(tmp_path):
    first = tmp_path / "first.json"
    first.write_text(CASE.format(name="first", tend=0.05, body='{"material": "soil", '
                                 '"min": [0, 0], "max": [0.4, 0.3]}, {"material": "rock", '
                                 '"min": [0.4, 0], "max": [0.6, 0.2]}'))
    done = run(first, "--output", str(tmp_path / "out1"))
    assert done.returncode == 0, done.stderr
    last = sorted((tmp_path / "out1").glob("particles_*.h5"))[-1]
    second = tmp_path / "second.json"
    second.write_text(CASE.format(name="second", tend=0.01, body='{"material": "soil", '
                                  f'"particle_list": "{last}"}}'))
    check = run(second, "--check")
    assert check.returncode == 0, check.stderr
    with h5py.File(last) as f:
        position = f["particles/position"][()]
        material = f["particles/material"][()]
        stress = f["particles/stress"][()]
    count = int(re.search(r"bodies\s+1, (\d+) particles", check.stdout).group(1))
    assert count == len(position) == 48 + 16
    done = run(second, "--output", str(tmp_path / "out2"))
    assert done.returncode == 0, done.stderr
    with h5py.File(tmp_path / "out2" / "particles_000000.h5") as f:
        order = np.lexsort(f["particles/position"][()].T[::-1])
        again = f["particles/position"][()][order]
        again_material = f["particles/material"][()][order]
        again_stress = f["particles/stress"][()][order]
    reference = np.lexsort(position.T[::-1])
    assert np.array_equal(again, position[reference])
    assert np.array_equal(again_material, material[reference])
    assert set(material) == {1, 2}
    assert np.array_equal(again_stress, stress[reference])


@pytest.mark.parametrize("change, message", [
    (lambda f: f["particles/volume"].__setitem__(0, -1.0), "particle 1: volume = -1"),
    (lambda f: f["particles/position"].__setitem__(0, [5.0, 0.1, 0.0]), "particle 1: the "
     "position (5, 0.1) m is outside the domain"),
    (lambda f: f["particles/material"].__setitem__(0, 7), "particle 1: material 7 is not a "
     "position in materials"),
    (lambda f: f.__delitem__("particles/position"), "has no dataset '/particles/position'"),
])
def test_a_bad_hdf5_list_is_refused(tmp_path, change, message):
    path = tmp_path / "list.h5"
    with h5py.File(path, "w") as f:
        f["particles/position"] = np.array([[0.05, 0.05, 0.0], [0.15, 0.05, 0.0]])
        f["particles/volume"] = np.array([0.0025, 0.0025])
        f["particles/material"] = np.array([1, 2], dtype=np.int32)
        change(f)
    case = tmp_path / "case.json"
    case.write_text(CASE.format(name="bad", tend=0.01, body='{"material": "soil", '
                                f'"particle_list": "{path}"}}'))
    check = run(case, "--check")
    assert check.returncode == 2
    assert message in check.stderr and "bodies[1].particle_list" in check.stderr
    assert check.stderr.count("\n") == 1
