"""gridlib.reproducible: exact-split matrix products and elementary functions give the same
bits whatever the BLAS kernel, its thread count and numpy's SIMD dispatch level; and the
library uses none of the machine-dependent numpy/BLAS calls in its own code."""

from __future__ import annotations

import ast
import math
import pathlib

import numpy as np
import pytest
from variants import same_output_everywhere

import gridlib
from gridlib import reproducible as rp

ROOT = pathlib.Path(gridlib.__file__).parent


def test_matmul_is_exact_split_and_accurate():
    rng = np.random.default_rng(7)
    for m, k, n in [(3, 2, 4), (5, 8, 3), (40, 9, 30), (120, 2000, 70), (7, 4097, 5)]:
        a = rng.normal(size=(m, k)) * rng.uniform(0.1, 1e6, (m, 1))
        b = rng.normal(size=(k, n)) * rng.uniform(1e-3, 10, (1, n))
        got = rp.matmul(a, b)
        exact = np.array([[math.fsum(a[i] * b[:, j]) for j in range(n)] for i in range(m)])
        # error bound of an ordinary product: k u max|a_i.| max|b_.j|
        bound = k * 2.0**-52 * np.abs(a).max(axis=1)[:, None] * np.abs(b).max(axis=0)[None, :]
        assert np.all(np.abs(got - exact) <= bound)
    assert rp.matmul(np.zeros((0, 3)), np.ones((3, 2))).shape == (0, 2)
    with pytest.raises(ValueError, match="finite"):
        rp.matmul(np.full((2, 20), np.nan), np.ones((20, 2)))
    with pytest.raises(ValueError, match="shapes"):
        rp.matmul(np.ones((2, 3)), np.ones((2, 3)))


def test_right_factor_gives_matmul_bits_block_after_block():
    """One right factor, blocks of rows of varying sizes in two threads (each reusing its
    workspace): every block's product has the bits of matmul's."""
    from concurrent.futures import ThreadPoolExecutor

    rng = np.random.default_rng(3)
    a = rng.normal(size=(700, 1500)) * rng.uniform(0.1, 1e3, (700, 1))
    for k, n in [(1500, 3), (5, 4)]:
        b = rng.normal(size=(k, n))
        product = rp.RightFactor(b)
        starts = [0, 128, 256, 300, 301, 500]
        blocks = [a[s:e, :k] for s, e in zip(starts, [*starts[1:], 700], strict=True)]
        with ThreadPoolExecutor(2) as pool:
            got = list(pool.map(product.times, blocks * 2))
        for block, product_bits in zip(blocks * 2, got, strict=True):
            assert np.array_equal(product_bits, rp.matmul(block, b))
    with pytest.raises(ValueError, match="finite"):
        rp.RightFactor(np.ones((20, 2))).times(np.full((2, 20), np.inf))
    with pytest.raises(ValueError, match="finite"):
        rp.RightFactor(np.full((20, 2), np.nan))
    with pytest.raises(ValueError, match="shapes"):
        rp.RightFactor(np.ones((20, 2))).times(np.ones((2, 19)))


def test_solve_small_large_and_batched():
    rng = np.random.default_rng(5)
    for shape in [(1, 1), (4, 4), (30, 12, 12), (1, 67, 67), (700, 700)]:
        a = rng.normal(size=shape) + 3 * np.eye(shape[-1])
        b = rng.normal(size=shape[:-1])
        x = rp.solve(a, b)
        assert x.shape == b.shape
        np.testing.assert_allclose(np.einsum("...ij,...j->...i", a, x), b, atol=1e-11)
    with pytest.raises(np.linalg.LinAlgError, match="singular"):
        rp.solve(np.ones((3, 3)), np.ones(3))
    with pytest.raises(ValueError, match="square"):
        rp.solve(np.ones((3, 2)), np.ones(3))


def test_elementary_functions_are_accurate():
    """Within 1 ulp (exp, log) and a few ulp (the others) of the C library's values, with
    its special values."""
    rng = np.random.default_rng(3)

    def ulps(got, ref):
        got, ref = np.asarray(got), np.asarray(ref)
        return float(np.max(np.where(got == ref, 0.0, np.abs(got - ref) / np.spacing(np.abs(ref)))))

    x = np.concatenate([rng.uniform(-745, 709, 20000), rng.uniform(-1, 1, 20000), rng.normal(0, 1e-9, 500)])
    e = rp.exp(x)
    assert ulps(e, [math.exp(v) for v in x]) <= 1.0
    assert np.mean(e == [math.exp(v) for v in x]) > 0.99  # nearly always correctly rounded
    p = np.concatenate([np.exp(rng.uniform(-740, 709, 20000)), rng.uniform(0.5, 2, 20000), [5e-324, 1e-310]])
    assert ulps(rp.log(p), [math.log(v) for v in p]) <= 1.0
    assert ulps(rp.log10(p), [math.log10(v) for v in p]) <= 3.0
    y, xx = rng.uniform(-1e3, 1e3, 20000), rng.uniform(-1e3, 1e3, 20000)
    assert ulps(rp.arctan2(y, xx), [math.atan2(a, b) for a, b in zip(y, xx, strict=True)]) <= 3.0
    u = rng.uniform(-1, 1, 20000)
    assert ulps(rp.arccos(u), [math.acos(v) for v in u]) <= 4.0
    assert ulps(rp.arcsin(u), [math.asin(v) for v in u]) <= 4.0
    b, c = rng.uniform(0.01, 10, 20000), rng.uniform(-5, 5, 20000)
    assert ulps(rp.power(b, c), [math.pow(s, t) for s, t in zip(b, c, strict=True)]) <= 32.0
    assert rp.power([3.0, -3.0, 1.5, 2.0], [5.0, 3.0, 2.0, -3.0]).tolist() == [243.0, -27.0, 2.25, 0.125]
    assert rp.exp([0.0, np.inf, -np.inf, 1000.0, -1000.0, np.nan]).tolist()[:5] == [
        1.0,
        np.inf,
        0.0,
        np.inf,
        0.0,
    ]
    assert np.isnan(rp.log(-1.0)) and rp.log(0.0) == -np.inf and rp.log(np.inf) == np.inf
    for yy, xv in [(0.0, -1.0), (-0.0, -1.0), (1.0, 0.0), (-1.0, 0.0), (np.inf, np.inf), (0.0, 0.0)]:
        assert rp.arctan2(yy, xv) == math.atan2(yy, xv)


CODE = """
import hashlib, numpy as np
from gridlib import reproducible as rp
rng = np.random.default_rng(11)
a, b = rng.normal(size=(300, 2000)), rng.normal(size=(2000, 150)) * 1e3
x = rng.uniform(-700, 700, 100000)
p = np.abs(x) + 1e-3
out = {
    "matmul": rp.matmul(a, b), "matmul_small": rp.matmul(a[:, :5], b[:5]),
    "exp": rp.exp(x), "log": rp.log(p), "log10": rp.log10(p), "power": rp.power(p % 7, x % 3),
    "arctan2": rp.arctan2(x, p - 300), "arccos": rp.arccos(np.cos(x)),
    "solve": rp.solve(a[:, :300] + 300 * np.eye(300), a[:, 0]), "solve_batch": rp.solve(
        a[:200, :60].reshape(20, 10, 60)[:, :, :10] + np.eye(10), a[:20, :10]),
    # numpy's own functions that gridlib uses as they are
    "sin": np.sin(x), "cos": np.cos(x), "sqrt": np.sqrt(p), "hypot": np.hypot(x, p),
    "sum": np.array([x.sum(), np.add.reduce(x.reshape(400, 250), axis=0).sum()]), "cumsum": np.cumsum(x),
    "einsum": np.einsum("ij,ij->i", x.reshape(-1, 4), p.reshape(-1, 4)),
    "einsum_axis0": np.einsum("mk,mk->k", x[:99999].reshape(3, -1), p[:99999].reshape(3, -1)),
    "bincount": np.bincount((p * 10).astype(int) % 100, weights=x), "norm": np.linalg.norm(a, axis=1),
    "cross": np.cross(x.reshape(-1, 4)[:, :3], p.reshape(-1, 4)[:, 1:]), "square": x**2,
}
# the random fields' sums: one right factor for many products, cos | sin written into row halves
out["right_factor"] = rp.RightFactor(b).times(a[:, :2000])
halves = np.empty((100, 2000))
np.cos(x.reshape(100, 1000), out=halves[:, :1000])
np.sin(x.reshape(100, 1000), out=halves[:, 1000:])
out["cos_sin_halves"] = halves
for k, v in out.items():
    print(k, hashlib.sha256(np.ascontiguousarray(v).tobytes()).hexdigest())
"""


def test_same_bits_for_every_blas_kernel_thread_count_and_simd_level():
    same_output_everywhere(CODE)


# Calls whose results depend on the CPU, the BLAS kernel or its thread count; the library
# uses gridlib.reproducible instead.
NUMPY_FORBIDDEN = {
    "exp", "exp2", "expm1", "log", "log2", "log10", "log1p", "power", "float_power", "tan", "arctan",
    "arctan2", "arcsin", "arccos", "arcsinh", "arccosh", "arctanh", "sinh", "cosh", "tanh", "cbrt",
    "dot", "matmul", "inner", "vdot", "tensordot", "logaddexp", "logaddexp2",
}  # fmt: skip
MATH_FORBIDDEN = {
    "exp", "log", "log2", "log10", "log1p", "expm1", "pow", "tan", "atan", "atan2", "asin", "acos",
    "sinh", "cosh", "tanh", "cbrt", "exp2",
}  # fmt: skip
ALLOWED_MARK = "# machine-independent:"  # a line may say why its call is exact anyway


def machine_dependent_calls(source: str) -> list[tuple[int, str]]:
    """(line, what) of every call in ``source`` that may round differently on another machine."""
    found = []
    lines = source.splitlines()
    for node in ast.walk(ast.parse(source)):
        what = None
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            owner = node.func.value
            name = node.func.attr
            if isinstance(owner, ast.Name) and owner.id == "np" and name in NUMPY_FORBIDDEN:
                what = f"np.{name}"
            elif isinstance(owner, ast.Name) and owner.id == "math" and name in MATH_FORBIDDEN:
                what = f"math.{name}"
            elif name == "norm" and not any(k.arg == "axis" for k in node.keywords):
                what = "norm of a vector (BLAS dot)"
            elif isinstance(owner, ast.Attribute) and owner.attr == "linalg" and name != "norm":
                what = f"linalg.{name} (LAPACK)"
        elif isinstance(node, ast.BinOp) and isinstance(node.op, ast.MatMult):
            what = "@ (BLAS)"
        elif isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            exponent = node.right
            exact = isinstance(exponent, ast.Constant) and exponent.value in (2, 2.0, 0.5, 1, -1)
            base = node.left.operand if isinstance(node.left, ast.UnaryOp) else node.left
            ints = isinstance(base, ast.Constant) and isinstance(base.value, int)  # Python integers
            if not (exact or ints):
                what = f"** {ast.unparse(exponent)} (numpy's power)"
        if what and ALLOWED_MARK not in lines[node.lineno - 1]:
            found.append((node.lineno, what))
    return found


def test_detector_finds_what_it_should():
    src = "import numpy as np\nimport math\nnp.exp(x)\na @ b\nx ** 3\nmath.atan2(y, x)\nnp.linalg.norm(v)\n"
    src += "np.linalg.solve(a, b)\nx ** 2\n2 ** 62\nnp.linalg.norm(v, axis=1)\nnp.sin(x)\n"
    src += "x ** k  # machine-independent: integer arrays\n"
    assert machine_dependent_calls(src) == [
        (3, "np.exp"), (4, "@ (BLAS)"), (5, "** 3 (numpy's power)"), (6, "math.atan2"),
        (7, "norm of a vector (BLAS dot)"), (8, "linalg.solve (LAPACK)"),
    ]  # fmt: skip


def test_library_makes_no_machine_dependent_calls():
    found = []
    for path in sorted(ROOT.rglob("*.py")):
        if path.name == "reproducible.py":
            continue
        for line, what in machine_dependent_calls(path.read_text()):
            found.append(f"{path.relative_to(ROOT.parent)}:{line}: {what}")
    assert not found, "use gridlib.reproducible instead:\n" + "\n".join(found)
