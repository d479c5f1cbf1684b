#!/usr/bin/env python3
"""Which loops of the particle kernels gfortran vectorises (issue 20 asks it to be said).

Compiles the files of the step's hot path (kernels, shape functions, materials, the transfer
passes, the particle geometry) with the flags the build gives each of them (CMake's
compile_commands.json, per-file options included) plus -fopt-info-vec, and prints per
procedure the loops the compiler vectorised (with the vector width) and those it did not (with
its first reason). Loops of a constant length of 2 or 3 that the compiler unrolls completely
are not loops any more and do not appear. By default only `do` loops are listed; with --all
also the array statements (most of them over the components of one particle's vectors).

The report is that of compiling each file on its own: the binary is linked with link-time
optimisation, which recompiles the fat objects after inlining across modules, so a loop of an
inlined routine can vectorise there differently (rarely: the kernels are written so that their
loops do not depend on the callers).

Usage: bench/vectorisation_report.py [--build BUILD] [--markdown] [--all]
  BUILD: a configured and built tree of this source (default: build); its module folder is
  used, nothing in it is written.
"""
import argparse
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
HOT = ["src/solver/kernels", "src/shape", "src/material", "src/solver/mpm_transfer.f90",
       "src/solver/mpm_step_passes.f90", "src/model/mpm_particles.f90"]
PROC = re.compile(r"^\s*(?:(?:pure|elemental|impure|recursive|module)\s+)*"
                  r"(?:(?:real|integer|logical)(?:\([^)]*\))?\s+)?"
                  r"(subroutine|function)\s+(\w+)", re.IGNORECASE)
END = re.compile(r"^\s*end\s+(subroutine|function)\b", re.IGNORECASE)
NOTE = re.compile(r"^(?P<file>[^:]+):(?P<line>\d+):(?P<col>\d+): (?P<kind>optimized|missed): "
                  r"(?P<text>.*)$")


def compile_commands(build):
    """The compile command of each source file, from a configure with the commands exported."""
    out = Path(tempfile.mkdtemp(prefix="vecreport_"))
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(out),
                    "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON",
                    "-DCMAKE_BUILD_TYPE=" + build_type(build)],
                   check=True, stdout=subprocess.DEVNULL)
    entries = json.loads((out / "compile_commands.json").read_text())
    return {Path(e["file"]).resolve(): e["command"] for e in entries}, out


def build_type(build):
    cache = Path(build) / "CMakeCache.txt"
    if cache.exists():
        for line in cache.read_text().splitlines():
            if line.startswith("CMAKE_BUILD_TYPE:"):
                return line.split("=", 1)[1] or "Release"
    return "Release"


def hot_files(commands):
    files = []
    for f in sorted(commands):
        rel = f.relative_to(ROOT).as_posix() if ROOT in f.parents else ""
        if rel.endswith(".f90") and any(rel == h or rel.startswith(h + "/") for h in HOT):
            files.append(f)
    return files


def procedures(path):
    """(first line, last line, name) of every procedure of a source or include file."""
    spans, stack = [], []
    for n, line in enumerate(path.read_text().splitlines(), 1):
        code = line.split("!", 1)[0]
        if END.match(code):
            if stack:
                start, name = stack.pop()
                spans.append((start, n, name))
            continue
        m = PROC.match(code)
        if m and not re.match(r"^\s*end\b", code, re.IGNORECASE):
            stack.append((n, m.group(2)))
    return spans


def enclosing(spans, line):
    best = None
    for start, end, name in spans:
        if start <= line <= end and (best is None or start >= best[0]):
            best = (start, name)
    return best[1] if best else "?"


def is_do_loop(path, line, cache={}):
    """Whether the statement at `line` of `path` is a do loop (else an array statement)."""
    if path not in cache:
        cache[path] = path.read_text().splitlines()
    text = cache[path][line - 1] if 0 < line <= len(cache[path]) else ""
    return re.match(r"^\s*(\w+\s*:\s*)?do\b", text, re.IGNORECASE) is not None


def report(build, everything=False):
    commands, scratch = compile_commands(build)
    mods = Path(build).resolve() / "mod"
    if not mods.is_dir():
        sys.exit(f"vectorisation_report: {mods} not found: build the tree first (make build)")
    loops = defaultdict(lambda: {"vectorised": {}, "missed": {}})
    for src in hot_files(commands):
        cmd = shlex.split(commands[src])
        keep, skip = [], False
        for arg in cmd:
            if skip:
                skip = False
                continue
            if arg == "-o":
                skip = True
                continue
            if arg.startswith("-flto") or arg == "-ffat-lto-objects" or arg.startswith("-J") \
                    or arg.startswith("-I"):
                continue
            keep.append(arg)
        with tempfile.TemporaryDirectory() as tmp:
            info = Path(tmp) / "vec.txt"
            run = keep + [f"-I{mods}", "-I/usr/include/hdf5/serial", f"-J{tmp}",
                          f"-I{src.parent}", "-o", str(Path(tmp) / "x.o"),
                          f"-fopt-info-vec-optimized-missed={info}"]
            done = subprocess.run(run, cwd=str(scratch), capture_output=True, text=True)
            if done.returncode != 0:
                sys.exit(f"vectorisation_report: compiling {src} failed:\n{done.stderr}")
            lines = info.read_text().splitlines() if info.exists() else []
        pending = None
        for text in lines:
            m = NOTE.match(text)
            if not m:
                continue
            where = (m["file"], int(m["line"]))
            body = m["text"]
            if m["kind"] == "optimized" and body.startswith("loop vectorized using"):
                width = body.split("using", 1)[1].strip()
                loops[where]["vectorised"].setdefault(width, True)
                pending = None
            elif body.startswith("couldn't vectorize loop"):
                pending = where
                loops[where]["missed"].setdefault("?", True)
            elif pending and body.startswith("not vectorized:"):
                reason = body.split(":", 1)[1].strip()
                reason = re.sub(r"_\d+|\.\d+", "", reason)[:80]
                loops[pending]["missed"] = {reason: True}
                pending = None
    # a loop vectorised in any of its versions counts as vectorised
    table = defaultdict(lambda: {"yes": [], "no": []})
    cache = {}
    for (file, line), what in sorted(loops.items()):
        path = resolve(file)
        if path is None:
            continue
        if not everything and not is_do_loop(path, line):
            continue
        if path not in cache:
            cache[path] = procedures(path)
        name = enclosing(cache[path], line)
        if name == "?" and path.suffix == ".inc":
            name = "(included by the variants)"
        key = (path.relative_to(ROOT).as_posix(), name)
        if what["vectorised"]:
            widths = ", ".join(sorted(what["vectorised"]))
            table[key]["yes"].append(f"{line} ({widths})")
        else:
            reason = next(iter(what["missed"]))
            table[key]["no"].append(f"{line} ({reason})" if reason != "?" else f"{line}")
    shutil_rm(scratch)
    return table


def resolve(file):
    p = Path(file)
    if p.is_absolute() and p.exists():
        return p.resolve()
    for folder in ["src/solver/kernels", "src/material", "src/shape", "src/solver", "src/model"]:
        q = ROOT / folder / p.name
        if q.exists():
            return q
    return None


def shutil_rm(folder):
    import shutil
    shutil.rmtree(folder, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build"))
    ap.add_argument("--markdown", action="store_true", help="a table for docs/performance.md")
    ap.add_argument("--all", action="store_true", help="array statements too, not only do loops")
    args = ap.parse_args()
    table = report(args.build, args.all)
    total_yes = sum(len(v["yes"]) for v in table.values())
    total_no = sum(len(v["no"]) for v in table.values())
    if args.markdown:
        print("| file | procedure | loops vectorised (line, vectors) | loops not vectorised (line, first reason) |")
        print("|---|---|---|---|")
        for (file, name), v in sorted(table.items()):
            print(f"| {file} | `{name}` | {'; '.join(v['yes']) or '-'} | {'; '.join(v['no']) or '-'} |")
    else:
        for (file, name), v in sorted(table.items()):
            print(f"{file}  {name}")
            for y in v["yes"]:
                print(f"    vectorised      line {y}")
            for n in v["no"]:
                print(f"    not vectorised  line {n}")
    print(f"\n{total_yes} {'loops' if args.all else 'do loops'} vectorised, {total_no} not (gfortran "
          f"{subprocess.run(['gfortran', '-dumpfullversion'], capture_output=True, text=True).stdout.strip()})")


if __name__ == "__main__":
    main()
