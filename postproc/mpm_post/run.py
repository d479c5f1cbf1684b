"""Run the mpm_geo executable from Python (validation and study scripts)."""

import subprocess
import time


def run_mpm_geo_status(exe, case_path, output, overwrite=False, quiet=False, cwd=None):
    """Run ``exe case_path --output output`` and return (wall time [s], exit code).

    ``overwrite`` adds ``--overwrite`` (only for a script's own output folder), ``quiet`` adds
    ``--quiet``. For a run whose failure is itself a result (a reported run that may stop).
    """
    command = [str(exe), str(case_path), "--output", str(output)]
    if overwrite:
        command.append("--overwrite")
    if quiet:
        command.append("--quiet")
    print("running:", " ".join(command), flush=True)
    start = time.perf_counter()
    result = subprocess.run(command, cwd=cwd, check=False)
    return time.perf_counter() - start, result.returncode


def run_mpm_geo(exe, case_path, output, overwrite=False, quiet=False, cwd=None):
    """Run ``exe case_path --output output`` and return its wall time [s].

    The options as for ``run_mpm_geo_status``. Raises RuntimeError naming the exit code when
    mpm_geo fails.
    """
    wall, code = run_mpm_geo_status(exe, case_path, output, overwrite, quiet, cwd)
    if code != 0:
        raise RuntimeError(f"mpm_geo exited with code {code} on {case_path} "
                           f"(output in {output})")
    return wall
