"""Error norms of a particle field against an analytic (exact) field.

The exact field is a Python callable ``f(x, t)`` (``x``: particle positions, an (n, 3) array
[m], z = 0 in 2D; ``t``: time [s]; returns n values or one) or a NumPy expression in ``x``,
``y``, ``z`` and ``t``, such as ``"-2650*9.81*(0.1 - y)"``, turned into such a callable by
``compile_expression``. Expressions are evaluated by walking their syntax tree, never by
``eval``: only numbers, the names above, ``pi`` and ``e``, arithmetic, comparisons and the
NumPy functions of ``FUNCTIONS`` (written ``sin(x)``, ``np.sin(x)`` or ``numpy.sin(x)``) are
accepted; anything else (attributes, subscripts, strings, keywords, builtins) is refused with
an ``ExpressionError`` naming it.

Norms of e = field - exact over the n particles, each weighted by w (mass, volume or 1):

- L1   = sum(w |e|) / sum(w)
- L2   = sqrt(sum(w e^2) / sum(w))
- Linf = max |e|

in the units of the field, and divided by a scale (default: max |exact|) as relative norms.
With volume weights L1 and L2 are the discrete mean and root-mean-square of the error over the
body; with mass weights, over its mass.
"""

import ast
from dataclasses import dataclass

import numpy as np

from .io import component_names

# Functions an expression may call: element-wise NumPy functions (and where/clip/minimum/...),
# nothing that reads files, allocates by size or reaches Python objects.
FUNCTIONS = frozenset([
    "abs", "absolute", "arccos", "arccosh", "arcsin", "arcsinh", "arctan", "arctan2",
    "arctanh", "cbrt", "ceil", "clip", "cos", "cosh", "deg2rad", "degrees", "exp", "exp2",
    "expm1", "fabs", "floor", "fmax", "fmin", "fmod", "heaviside", "hypot", "log", "log10",
    "log1p", "log2", "logical_and", "logical_not", "logical_or", "maximum", "minimum", "mod",
    "power", "rad2deg", "radians", "sign", "sin", "sinc", "sinh", "sqrt", "square", "tan",
    "tanh", "where",
])
CONSTANTS = {"pi": np.pi, "e": np.e}
VARIABLES = ("x", "y", "z", "t")
NUMPY_MODULES = ("np", "numpy")
MAX_EXPRESSION_LENGTH = 2000
MAX_EXPRESSION_DEPTH = 200    # nesting of the syntax tree, well inside Python's recursion limit

_BINARY = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply,
           ast.Div: np.true_divide, ast.Pow: np.power, ast.Mod: np.mod,
           ast.FloorDiv: np.floor_divide}
_UNARY = {ast.USub: np.negative, ast.UAdd: np.positive}
_COMPARE = {ast.Lt: np.less, ast.LtE: np.less_equal, ast.Gt: np.greater,
            ast.GtE: np.greater_equal, ast.Eq: np.equal, ast.NotEq: np.not_equal}

NORMS = ("l1", "l2", "linf")
WEIGHTS = ("mass", "volume", "none")
# Units of the fields of docs/output.md, for messages and tables.
FIELD_UNITS = {"position": "m", "displacement": "m", "velocity": "m/s", "stress": "Pa",
               "strain": "-", "plastic_strain": "-", "mass": "kg", "volume": "m3"}


class ExpressionError(ValueError):
    """An exact-field expression that cannot be parsed or uses something not allowed."""


def _refuse(node, text, what):
    column = getattr(node, "col_offset", None)
    where = f" at column {column + 1}" if column is not None else ""
    raise ExpressionError(f"{what}{where} is not allowed in the expression '{text}' (allowed: "
                          f"numbers, {', '.join(VARIABLES)}, pi, e, + - * / ** % //, "
                          "comparisons and NumPy functions such as sin, exp, sqrt, where)")


def _function_name(node, text):
    """The NumPy function a call refers to: ``sin``, ``np.sin`` or ``numpy.sin``."""
    if isinstance(node, ast.Name):
        name = node.id
    elif (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
          and node.value.id in NUMPY_MODULES):
        name = node.attr
    else:
        target = ast.get_source_segment(text, node) or type(node).__name__
        _refuse(node, text, f"calling '{target}'")
    if name not in FUNCTIONS:
        raise ExpressionError(f"unknown function '{name}' in the expression '{text}' "
                              f"(allowed: {', '.join(sorted(FUNCTIONS))})")
    return name


def _check(node, text):
    """Raise ExpressionError unless every node of the tree is an allowed one."""
    if isinstance(node, ast.Expression):
        _check(node.body, text)
    elif isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
            _refuse(node, text, f"the constant {node.value!r}")
    elif isinstance(node, ast.Name):
        if node.id not in VARIABLES and node.id not in CONSTANTS:
            hint = " (a function name must be called)" if node.id in FUNCTIONS else ""
            raise ExpressionError(f"unknown name '{node.id}' in the expression '{text}' "
                                  f"(names: {', '.join(VARIABLES)}, pi, e){hint}")
    elif isinstance(node, ast.BinOp):
        if type(node.op) not in _BINARY:
            _refuse(node, text, f"the operator {type(node.op).__name__}")
        _check(node.left, text)
        _check(node.right, text)
    elif isinstance(node, ast.UnaryOp):
        if type(node.op) not in _UNARY:
            _refuse(node, text, f"the operator {type(node.op).__name__}")
        _check(node.operand, text)
    elif isinstance(node, ast.Compare):
        for op in node.ops:
            if type(op) not in _COMPARE:
                _refuse(node, text, f"the comparison {type(op).__name__}")
        for operand in [node.left, *node.comparators]:
            _check(operand, text)
    elif isinstance(node, ast.Call):
        _function_name(node.func, text)
        if node.keywords:
            _refuse(node, text, "a keyword argument")
        for arg in node.args:
            if isinstance(arg, ast.Starred):
                _refuse(arg, text, "a starred argument")
            _check(arg, text)
    else:
        _refuse(node, text, f"'{ast.get_source_segment(text, node) or type(node).__name__}'")


def _evaluate(node, names):
    """Value of a checked tree; numbers become float64 so that ** cannot run away."""
    if isinstance(node, ast.Expression):
        return _evaluate(node.body, names)
    if isinstance(node, ast.Constant):
        return np.float64(node.value)
    if isinstance(node, ast.Name):
        return names[node.id]
    if isinstance(node, ast.BinOp):
        return _BINARY[type(node.op)](_evaluate(node.left, names), _evaluate(node.right, names))
    if isinstance(node, ast.UnaryOp):
        return _UNARY[type(node.op)](_evaluate(node.operand, names))
    if isinstance(node, ast.Compare):
        # a < b < c is (a < b) and (b < c), element-wise
        left = _evaluate(node.left, names)
        result = True
        for op, comparator in zip(node.ops, node.comparators):
            right = _evaluate(comparator, names)
            result = np.logical_and(result, _COMPARE[type(op)](left, right))
            left = right
        return result
    if isinstance(node, ast.Call):
        function = getattr(np, _function_name(node.func, ""))
        return function(*[_evaluate(arg, names) for arg in node.args])
    raise AssertionError(f"unchecked node {type(node).__name__}")  # _check refuses these


def _depth(tree):
    """Depth of a syntax tree, walked without recursion."""
    deepest, stack = 0, [(tree, 1)]
    while stack:
        node, depth = stack.pop()
        deepest = max(deepest, depth)
        stack.extend((child, depth + 1) for child in ast.iter_child_nodes(node))
    return deepest


def compile_expression(text):
    """A callable ``f(x, t)`` evaluating the NumPy expression ``text`` in x, y, z and t.

    ``x`` of the callable is the (n, 3) position array [m]; the expression sees its columns as
    ``x``, ``y``, ``z`` and the time [s] as ``t``. Raises ExpressionError at once for a syntax
    error, an unknown name or function, or anything not allowed (see the module docstring).
    """
    if not isinstance(text, str) or not text.strip():
        raise ExpressionError("the exact expression is empty")
    if len(text) > MAX_EXPRESSION_LENGTH:
        raise ExpressionError(f"the exact expression is longer than {MAX_EXPRESSION_LENGTH} "
                              "characters")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(f"syntax error in the expression '{text}': {exc.msg}") from None
    except (RecursionError, MemoryError, ValueError):
        raise ExpressionError(f"cannot parse the expression '{text}'") from None
    if _depth(tree) > MAX_EXPRESSION_DEPTH:
        raise ExpressionError(f"the expression '{text}' is nested more than "
                              f"{MAX_EXPRESSION_DEPTH} levels deep")
    _check(tree, text.strip())

    def exact(x, t):
        x = np.asarray(x, dtype=float)
        if x.ndim != 2 or x.shape[1] != 3:
            raise ValueError(f"positions must be an (n, 3) array, got shape {x.shape}")
        names = dict(CONSTANTS, x=x[:, 0], y=x[:, 1], z=x[:, 2], t=np.float64(t))
        with np.errstate(all="ignore"):  # a nan or inf result is reported by the caller
            try:
                return _evaluate(tree, names)
            except (TypeError, ValueError, ArithmeticError) as exc:
                raise ValueError(f"cannot evaluate the expression '{text}': {exc}") from None

    exact.expression = text
    return exact


def exact_values(exact, position, time):
    """The exact field at ``position`` ((n, 3) [m]) and ``time`` [s] as n finite floats.

    ``exact`` is a callable ``f(x, t)`` or an expression string (see compile_expression).
    A scalar result is the same value at every particle. Raises ValueError for a result of
    another shape or with nan or inf values (naming how many and the first position).
    """
    if isinstance(exact, str):
        exact = compile_expression(exact)
    position = np.asarray(position, dtype=float)
    n = position.shape[0]
    values = np.asarray(exact(position, float(time)), dtype=float)
    if values.ndim == 0:
        values = np.full(n, float(values))
    values = values.reshape(-1) if values.size == n else values
    if values.shape != (n,):
        raise ValueError(f"the exact field has shape {values.shape}, expected ({n},): one "
                         "value per particle")
    bad = ~np.isfinite(values)
    if np.any(bad):
        first = position[np.argmax(bad)]
        raise ValueError(f"the exact field is not finite at {int(bad.sum())} of {n} particles "
                         f"(first at x = {first[0]:g}, y = {first[1]:g}, z = {first[2]:g})")
    return values


@dataclass(frozen=True)
class ErrorNorms:
    """Norms of field - exact [units of the field] and the scale [same units] they divide."""

    l1: float
    l2: float
    linf: float
    scale: float
    count: int

    def absolute(self, norm):
        """One norm by name: ``l1``, ``l2`` or ``linf``."""
        if norm not in NORMS:
            raise ValueError(f"unknown norm '{norm}' (norms: {', '.join(NORMS)})")
        return getattr(self, norm)

    def relative(self, norm):
        """One norm divided by the scale; nan when the scale is 0."""
        return self.absolute(norm) / self.scale if self.scale > 0.0 else float("nan")


def error_norms(values, exact, weights=None, scale=None):
    """L1, L2 and Linf norms of ``values - exact`` (see the module docstring).

    ``values``, ``exact``: n numbers each; ``weights``: n weights >= 0 with a positive sum
    (mass [kg] or volume [m3]), or None for equal weights; ``scale``: the value the relative
    norms divide by (default: max |exact|). Returns an ErrorNorms.
    """
    values = np.asarray(values, dtype=float).reshape(-1)
    exact = np.asarray(exact, dtype=float).reshape(-1)
    if values.shape != exact.shape:
        raise ValueError(f"{values.size} field values but {exact.size} exact values")
    if values.size == 0:
        raise ValueError("no particle: no error norm to compute")
    if weights is None:
        weights = np.ones(values.size)
    weights = np.asarray(weights, dtype=float).reshape(-1)
    if weights.shape != values.shape:
        raise ValueError(f"{weights.size} weights for {values.size} particles")
    if np.any(weights < 0.0) or not np.all(np.isfinite(weights)) or not weights.sum() > 0.0:
        raise ValueError("weights must be finite, >= 0 and not all 0")
    if not np.all(np.isfinite(values)):
        raise ValueError(f"the particle field has {int(np.sum(~np.isfinite(values)))} "
                         "non-finite values")
    error = np.abs(values - exact)
    total = weights.sum()
    if scale is None:
        scale = float(np.max(np.abs(exact)))
    elif not (np.isfinite(scale) and scale > 0.0):
        raise ValueError(f"scale must be a positive number, got {scale}")
    return ErrorNorms(l1=float(np.sum(weights * error) / total),
                      l2=float(np.sqrt(np.sum(weights * error**2) / total)),
                      linf=float(np.max(error)), scale=float(scale), count=int(values.size))


def field_component(data, field, component=None):
    """One column of a particle field of ``data`` (a dict from load_particles) as n floats.

    ``component``: a column name of the field (``x y z`` for vectors, ``xx yy zz xy [yz zx]``
    for stress and strain) or ``magnitude`` for a vector field; None for a one-column field.
    Raises KeyError naming the fields, or the components, there are.
    """
    fields = sorted(k for k, v in data.items() if isinstance(v, np.ndarray))
    if field not in fields:
        raise KeyError(f"no field '{field}' in {data.get('path', 'the output')} "
                       f"(fields: {', '.join(fields)})")
    array = np.asarray(data[field], dtype=float)
    if array.ndim == 1:
        if component not in (None, field):
            raise KeyError(f"field '{field}' has one value per particle: no component "
                           f"'{component}'")
        return array
    names = component_names(field, array)
    if component == "magnitude" and names == ["x", "y", "z"]:
        return np.linalg.norm(array, axis=1)
    if component not in names:
        extra = ", magnitude" if names == ["x", "y", "z"] else ""
        given = "no component given" if component is None else f"no component '{component}'"
        raise KeyError(f"{given} for field '{field}' (components: {', '.join(names)}{extra})")
    return array[:, names.index(component)]


def particle_weights(data, weight):
    """Per-particle weights of ``data``: its ``mass``, its ``volume``, or ones for ``none``."""
    if weight not in WEIGHTS:
        raise ValueError(f"unknown weight '{weight}' (weights: {', '.join(WEIGHTS)})")
    n = data["position"].shape[0]
    if weight == "none":
        return np.ones(n)
    if weight not in data:
        raise KeyError(f"no field '{weight}' in {data.get('path', 'the output')} to weight the "
                       "norms with: use another weight or 'none'")
    return np.asarray(data[weight], dtype=float)


def particle_error(data, field, component, exact, weight="mass", scale=None,
                   coordinates="current"):
    """Error norms of one particle field of an output against an exact field.

    ``data``: a dict from load_particles; ``field``, ``component``: as in field_component;
    ``exact``: a callable f(x, t) or an expression (see compile_expression), evaluated at the
    output's time and at the particles' ``current`` positions, or at their ``initial`` ones
    (position - displacement, for solutions written in the reference configuration);
    ``weight``: ``mass``, ``volume`` or ``none``; ``scale``: as in error_norms.
    Returns an ErrorNorms.
    """
    if isinstance(exact, str):
        exact = compile_expression(exact)
    values = field_component(data, field, component)
    position = np.asarray(data["position"], dtype=float)
    if coordinates == "initial":
        if "displacement" not in data:
            raise KeyError(f"no field 'displacement' in {data.get('path', 'the output')}: the "
                           "initial positions are unknown")
        position = position - np.asarray(data["displacement"], dtype=float)
    elif coordinates != "current":
        raise ValueError(f"coordinates must be 'current' or 'initial', got '{coordinates}'")
    expected = exact_values(exact, position, data["time"])
    return error_norms(values, expected, particle_weights(data, weight), scale)
