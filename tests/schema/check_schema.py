"""Check docs/case.schema.json against the case reader and the shipped cases.

    check_schema.py --keys-program build/print_case_keys [--exe build/mpm_geo]

1. The key paths of the schema and those the reader accepts (printed by print_case_keys from
   the reader's own key lists) are the same set; every object of the schema refuses unknown
   keys (additionalProperties: false), as the reader does. The names of the keys that choose
   an extension (output fields, material types, boundary conditions, shape functions; printed
   from the registries as "=<path> <name>") are those of the schema's enum for that key.
2. Every case shipped in inputs/, validation/, bench/cases/ and tests/parallel/cases/ is valid
   (JSON files under a results/ folder are metrics, not cases).
3. The hostile cases of tests/bad_inputs/ that a schema can detect are invalid.
4. Small variations of a valid case (per-type material keys, alternatives, 2D/3D vectors,
   letter case of choices): the schema gives the expected verdict and, with --exe, so does
   `mpm_geo --check`.

Run from the repository root (CTest does). Exit 0 when every check passes.
"""

import argparse
import copy
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import jsonschema

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = ROOT / "docs" / "case.schema.json"
CASE_DIRS = ["inputs", "validation", "bench/cases", "tests/parallel/cases"]

# tests/bad_inputs files whose fault a schema sees (types, ranges, unknown or missing keys);
# the others are left to the reader: text that is not JSON (nan_dx's NaN included), numbers
# that overflow (inf_E), files that do not exist or are not closed surfaces, duplicate names,
# geometry (bodies outside the domain or overlapping) and sizes (huge_grid's node count).
SCHEMA_DETECTABLE = [
    "bad_boundary_type", "cfl_above_one", "empty_bodies", "empty_materials",
    "gravity_wrong_length", "huge_ppc", "missing_bodies", "missing_domain",
    "missing_materials", "mohr_coulomb_negative_phi", "negative_E", "negative_cfl",
    "negative_density", "negative_dx", "negative_nx", "negative_output_interval",
    "negative_tend", "poisson_half", "unknown_domain_key", "unknown_material_key",
    "unknown_material_type", "unknown_output_field", "unknown_top_key", "wrong_type_dx_array",
    "wrong_type_gravity_string", "wrong_type_materials_object", "wrong_type_nx_string",
    "wrong_type_ppc_float", "wrong_type_tend_bool", "zero_dx", "zero_ppc", "zero_size_domain",
    "name_too_long", "save_state_name_too_long", "output_directory_too_long",
    "absorbing_face_negative_vp",
]

BASE = {
    "name": "schema_probe",
    "domain": {"nx": 10, "ny": 5, "dx": 0.1},
    "materials": [{"name": "m", "type": "linear_elastic", "E": 1.0e6, "nu": 0.3, "rho": 2000}],
    "bodies": [{"name": "b", "material": "m", "min": [0.2, 0.0], "max": [0.5, 0.3]}],
    "gravity": [0, -9.81],
    "time": {"tend": 0.01},
}
MOHR_COULOMB = {"name": "m", "type": "mohr_coulomb", "E": 1.0e6, "nu": 0.3, "rho": 2000,
                "phi": 30}
NEWTONIAN = {"name": "m", "type": "newtonian", "rho": 1000, "viscosity": 0.001,
             "bulk_modulus": 2.0e6}


def variant(*edits):
    """BASE with edits applied: (dotted path, value), value None deletes the key."""
    case = copy.deepcopy(BASE)
    for path, value in edits:
        keys = path.split(".")
        node = case
        for key in keys[:-1]:
            node = node[int(key)] if isinstance(node, list) else node.setdefault(key, {})
        if value is None:
            del node[keys[-1]]
        elif isinstance(node, list):
            node[int(keys[-1])] = copy.deepcopy(value)
        else:
            node[keys[-1]] = copy.deepcopy(value)
    return case


# (what, case, valid): each verdict holds for the schema and for the reader
PROBES = [
    ("the base case", variant(), True),
    ("choices in any letter case", variant(("solver", {"scheme": "musl",
                                                       "shape_function": "CPGIMP"}),
                                           ("output", {"fields": ["Stress", "plastic_strain"]})),
     True),
    ("material type in any letter case",
     variant(("materials.0", dict(MOHR_COULOMB, type="Mohr_Coulomb"))), True),
    ("a Mohr-Coulomb material", variant(("materials.0", MOHR_COULOMB)), True),
    ("Mohr-Coulomb without phi",
     variant(("materials.0", MOHR_COULOMB), ("materials.0.phi", None)), False),
    ("cone in a Mohr-Coulomb material",
     variant(("materials.0", dict(MOHR_COULOMB, cone="compression"))), False),
    ("cone in a Drucker-Prager material",
     variant(("materials.0", dict(MOHR_COULOMB, type="drucker_prager", cone="compression"))),
     True),
    ("phi in a linear elastic material", variant(("materials.0.phi", 30)), False),
    ("a newtonian material", variant(("materials.0", NEWTONIAN)), True),
    ("E in a newtonian material", variant(("materials.0", dict(NEWTONIAN, E=1.0e6))), False),
    ("linear softening", variant(("materials.0", dict(
        MOHR_COULOMB, c=1000, softening={"type": "linear", "c_residual": 100, "strain": 0.1}))),
     True),
    ("linear softening without strain", variant(("materials.0", dict(
        MOHR_COULOMB, softening={"type": "linear", "phi_residual": 20}))), False),
    ("softening none with a strain", variant(("materials.0", dict(
        MOHR_COULOMB, softening={"type": "none", "strain": 0.1}))), False),
    ("dt and cfl together", variant(("time", {"tend": 0.01, "dt": 1e-5, "cfl": 0.5})), False),
    ("cfl above 1 with allow_unstable",
     variant(("time", {"tend": 0.01, "cfl": 1.5, "allow_unstable": True})), True),
    ("a frictional face", variant(("domain.boundaries",
                                   {"ymin": {"type": "Frictional", "mu": 0.4},
                                    "xmin": {"type": "fixed"}})), True),
    ('the string "frictional"', variant(("domain.boundaries", {"ymin": "frictional"})), False),
    ("a frictional face without mu",
     variant(("domain.boundaries", {"ymin": {"type": "frictional"}})), False),
    ("mu on a fixed face",
     variant(("domain.boundaries", {"ymin": {"type": "fixed", "mu": 0.1}})), False),
    ("an absorbing face", variant(("domain.boundaries",
                                   {"ymin": {"type": "Absorbing", "vp": 300, "vs": 160}})), True),
    ('the string "absorbing"', variant(("domain.boundaries", {"ymin": "absorbing"})), False),
    ("an absorbing face without vs",
     variant(("domain.boundaries", {"ymin": {"type": "absorbing", "vp": 300}})), False),
    ("an absorbing face with vp = 0",
     variant(("domain.boundaries", {"ymin": {"type": "absorbing", "vp": 0, "vs": 1}})), False),
    ("vs on a sliding face",
     variant(("domain.boundaries", {"ymin": {"type": "sliding", "vs": 100}})), False),
    ("a z face in 2D", variant(("domain.boundaries", {"zmin": "fixed"})), False),
    ("a 3D case", variant(("domain.nz", 4), ("gravity", [0, 0, -9.81]),
                          ("bodies.0.min", [0.2, 0.0, 0.0]), ("bodies.0.max", [0.5, 0.3, 0.3]),
                          ("domain.boundaries", {"zmin": "fixed"})), True),
    ("a 2D gravity in 3D", variant(("domain.nz", 4), ("bodies.0.min", [0.2, 0.0, 0.0]),
                                   ("bodies.0.max", [0.5, 0.3, 0.3])), False),
    ("dimension 3 without nz", variant(("dimension", 3)), False),
    ("dimension 2 with nz", variant(("dimension", 2), ("domain.nz", 4)), False),
    ("a random distribution with its seed",
     variant(("particles", {"distribution": "random", "seed": 7})), True),
    ("a seed without the random distribution", variant(("particles", {"seed": 7})), False),
    ("local damping", variant(("damping", {"type": "local", "value": 0.1})), True),
    ("local damping without value", variant(("damping", {"type": "local"})), False),
    ("a damping value without local damping", variant(("damping", {"value": 0.1})), False),
    ("flip_fraction with apic",
     variant(("solver", {"transfer": "apic", "flip_fraction": 0.9})), False),
    ("xpic of order 3", variant(("solver", {"transfer": "XPIC", "xpic_order": 3})), True),
    ("xpic of order 0", variant(("solver", {"transfer": "xpic", "xpic_order": 0})), False),
    ("xpic_order with flip", variant(("solver", {"xpic_order": 2})), False),
    ("flip_fraction with xpic",
     variant(("solver", {"transfer": "xpic", "flip_fraction": 0.9})), False),
    ("flip_fraction with flip", variant(("solver", {"flip_fraction": 0.9})), True),
    ("a body with file and min", variant(("bodies.0.file", "x.stl")), False),
    ("scale on a box body", variant(("bodies.0.scale", 2.0)), False),
    ("a body without min", variant(("bodies.0.min", None)), False),
    ("mu without terrain contact", variant(("contact", {"mu": 0.4})), False),
    ("a name with a blank", variant(("name", "my case")), False),
    # the longest names and paths (names of files and folders on Linux: 255 bytes, paths 4095)
    ("a name of 246 characters", variant(("name", "n" * 246)), True),
    ("a name of 247 characters", variant(("name", "n" * 247)), False),
    ("save_state with a file name of 251 characters", variant(("save_state", "s" * 251)), True),
    ("save_state with a file name of 252 characters", variant(("save_state", "s" * 252)), False),
    ("an output folder of 3839 characters",
     variant(("output", {"directory": "/".join(["d" * 255] * 15)})), True),
    ("an output folder of 3841 characters",
     variant(("output", {"directory": "/".join(["d" * 255] * 15) + "/x"})), False),
    ("an output folder name of 256 characters",
     variant(("output", {"directory": "out/" + "d" * 256})), False),
    ("a checkpoint file of 4092 characters",
     variant(("checkpoint", {"file": "/".join(["c" * 250] * 16) + "/" + "c" * 76})), False),
    ("an empty string", variant(("save_state", "")), False),
    ("checkpoint and guard", variant(("checkpoint", {"every_steps": 100, "every_minutes": 5,
                                                     "file": "c.h5", "on_signal": False}),
                                     ("guard", {"energy_factor": 5, "snapshot_steps": 0})),
     True),
    ("checkpoint every 0 steps", variant(("checkpoint", {"every_steps": 0})), False),
    ("a guard factor of 0", variant(("guard", {"energy_factor": 0})), False),
    ("the guard's copy in memory", variant(("guard", {"snapshot_in": "memory"})), True),
    ("the guard's copy on a disk", variant(("guard", {"snapshot_in": "disk"})), False),
    ("a $schema key (the reader refuses unknown keys)",
     variant(("$schema", "../docs/case.schema.json")), False),
]


def resolve(node, schema):
    """The schema a local $ref points to, or the node itself."""
    while isinstance(node, dict) and "$ref" in node:
        ref = node["$ref"]
        if not ref.startswith("#/"):
            raise ValueError(f"only local references are expected, found {ref}")
        target = schema
        for part in ref[2:].split("/"):
            target = target[part]
        node = target
    return node


def type_variants(node, schema):
    """[(type name, schema)] of an object whose keys depend on its "type" (the materials):
    allOf branches {if: ..., then: S} where S's "type" property lists its names in an enum."""
    variants = []
    for branch in node.get("allOf", []):
        then = resolve(branch.get("then"), schema)
        if "if" not in branch or not isinstance(then, dict):
            continue
        type_schema = resolve(then.get("properties", {}).get("type"), schema)
        if not isinstance(type_schema, dict):
            continue
        for option in [type_schema] + type_schema.get("anyOf", []):
            for name in option.get("enum", []):
                variants.append((name, then))
    return variants


def join(path, key):
    return f"{path}.{key}" if path else key


def collect(node, path, schema, paths, open_objects):
    """Add the key paths an object schema allows at `path` (reader notation: "a.b",
    "list[].key", "materials[type=NAME].key"); note objects that accept unknown keys."""
    node = resolve(node, schema)
    if not isinstance(node, dict):
        return
    for word in ("allOf", "anyOf", "oneOf"):
        for sub in node.get(word, []):
            collect(sub, path, schema, paths, open_objects)
    for word in ("then", "else"):  # "if" and "not" only test, they allow no key
        if word in node:
            collect(node[word], path, schema, paths, open_objects)
    if node.get("type") == "object" and node.get("additionalProperties") is not False \
            and not type_variants(node, schema):
        open_objects.append(path or "(top level)")
    for key, sub in node.get("properties", {}).items():
        paths.add(join(path, key))
        collect(sub, join(path, key), schema, paths, open_objects)
    if "items" in node:
        items = resolve(node["items"], schema)
        variants = type_variants(items, schema) if isinstance(items, dict) else []
        if variants:
            for name, sub in variants:
                collect(sub, f"{path}[type={name}]", schema, paths, open_objects)
        else:
            collect(items, path + "[]", schema, paths, open_objects)


def schema_key_paths(schema):
    paths, open_objects = set(), []
    collect(schema, "", schema, paths, open_objects)
    return paths, open_objects


# where the schema lists the names of each key that chooses an extension (JSON pointers of the
# objects whose "enum" lists hold them)
CHOICE_POINTERS = {
    "output.fields": ["properties/output/properties/fields/items/anyOf/0"],
    "materials.type": ["properties/materials/items/properties/type/anyOf/0"],
    "domain.boundaries.type": ["definitions/face/anyOf/0/anyOf/0",
                               "definitions/face/anyOf/1/properties/type/anyOf/0"],
    "solver.shape_function": ["properties/solver/properties/shape_function/anyOf/0"],
}


def schema_choices(schema, pointers):
    """The names of the enums at the JSON pointers."""
    names = set()
    for pointer in pointers:
        node = schema
        for part in pointer.split("/"):
            node = node[int(part)] if isinstance(node, list) else node[part]
        names.update(node["enum"])
    return names


def load_json(path):
    """A JSON file, refusing NaN and Infinity, which Python accepts but JSON has not."""
    def refuse(constant):
        raise ValueError(f"{constant} is not JSON")
    return json.loads(path.read_text(), parse_constant=refuse)


def first_error(validator, case):
    """Text of the most relevant error, or None for a valid case."""
    error = jsonschema.exceptions.best_match(validator.iter_errors(case))
    if error is None:
        return None
    where = "/".join(str(p) for p in error.absolute_path) or "(top level)"
    return f"{where}: {error.message}"


def reader_accepts(exe, case):
    """Whether `mpm_geo --check` accepts the case (exit 0) or refuses it (exit 2)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "probe.json"
        path.write_text(json.dumps(case))
        run = subprocess.run([exe, "--check", str(path)], capture_output=True, text=True,
                             cwd=ROOT, timeout=60, check=False)
    if run.returncode not in (0, 2):
        raise RuntimeError(f"mpm_geo --check exited {run.returncode}: {run.stderr.strip()}")
    return run.returncode == 0, run.stderr.strip()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keys-program", required=True,
                        help="program printing the reader's key paths (print_case_keys)")
    parser.add_argument("--exe", help="mpm_geo: also check the reader's verdict on the probes")
    args = parser.parse_args()

    failures = []
    schema = json.loads(SCHEMA.read_text())
    jsonschema.Draft7Validator.check_schema(schema)
    validator = jsonschema.Draft7Validator(schema)

    # 1. the same keys as the reader
    run = subprocess.run([args.keys_program], capture_output=True, text=True, check=True)
    lines = [line.strip() for line in run.stdout.splitlines() if line.strip()]
    reader = {line for line in lines if not line.startswith("=")}
    registry = {}
    for line in lines:
        if line.startswith("="):
            path, name = line[1:].split()
            registry.setdefault(path, set()).add(name)
    ours, open_objects = schema_key_paths(schema)
    for key in sorted(reader - ours):
        failures.append(f"key '{key}' is accepted by the reader but missing from the schema")
    for key in sorted(ours - reader):
        failures.append(f"key '{key}' is in the schema but the reader does not accept it")
    for path in open_objects:
        failures.append(f"object '{path}' of the schema accepts unknown keys "
                        "(additionalProperties is not false)")
    print(f"keys: {len(reader)} in the reader, {len(ours)} in the schema")
    if set(registry) != set(CHOICE_POINTERS):
        failures.append(f"print_case_keys lists the names of {sorted(registry)}, "
                        f"this check knows {sorted(CHOICE_POINTERS)}")
    for path, pointers in CHOICE_POINTERS.items():
        names = schema_choices(schema, pointers)
        for name in sorted(registry.get(path, set()) - names):
            failures.append(f"{path} = '{name}' is a name of the registry but missing from "
                            "the schema's enum")
        for name in sorted(names - registry.get(path, set())):
            failures.append(f"{path} = '{name}' is in the schema's enum but no registry "
                            "entry has it")
    print(f"choices: {sum(len(v) for v in registry.values())} names of "
          f"{len(registry)} registries compared with the schema")

    # 2. the shipped cases are valid
    cases = sorted(p for d in CASE_DIRS for p in (ROOT / d).rglob("*.json")
                   if "results" not in p.relative_to(ROOT).parts)
    for path in cases:
        message = first_error(validator, load_json(path))
        if message:
            failures.append(f"{path.relative_to(ROOT)} is refused by the schema: {message}")
    print(f"shipped cases: {len(cases)} validated")
    if len(cases) < 10:
        failures.append(f"only {len(cases)} shipped cases found under {CASE_DIRS}")

    # 3. hostile cases that a schema can see are refused
    for name in SCHEMA_DETECTABLE:
        path = ROOT / "tests" / "bad_inputs" / f"{name}.json"
        if first_error(validator, load_json(path)) is None:
            failures.append(f"{path.relative_to(ROOT)} is accepted by the schema")
    print(f"bad inputs: {len(SCHEMA_DETECTABLE)} checked to be refused")

    # 4. probes: the expected verdict from the schema and from the reader
    for what, case, valid in PROBES:
        message = first_error(validator, case)
        if (message is None) != valid:
            failures.append(f"probe '{what}': the schema says "
                            f"{'valid' if message is None else 'invalid (' + message + ')'}, "
                            f"expected {'valid' if valid else 'invalid'}")
        if args.exe:
            accepted, stderr = reader_accepts(args.exe, case)
            if accepted != valid:
                failures.append(f"probe '{what}': mpm_geo --check says "
                                f"{'valid' if accepted else 'invalid (' + stderr + ')'}, "
                                f"expected {'valid' if valid else 'invalid'}")
    print(f"probes: {len(PROBES)} checked" + (" with the schema and the reader" if args.exe
                                              else " with the schema"))

    for failure in failures:
        print("FAIL:", failure)
    print(f"case schema: {'FAILED' if failures else 'passed'} ({len(failures)} failures)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
