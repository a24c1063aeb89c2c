"""The constraint outputs on every path: the written module's contact_jacobian, contact_jacobian_dot_u and
closure_residual, and plain C's <name>_J_c, <name>_Jdot_c_u and <name>_closure (write_c, compiled) equal
the NumPy functions (a four-bar, a spatial loop between two branches, a rolling disk, random trees with a
loop closed at a drawn state); the rolling disk's outputs equal its closed forms, a closed loop's residual
is zero; row names cannot inject code into either."""
from __future__ import annotations

import ast
import re
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings

import eomgen as eg
import strategies as S
from test_loop_rows import COMMON, closed_tree, loops
from test_outputs import load
from test_rolling_rows import closed_forms, disk

KEYS = ("J_c", "Jdot_c_u", "closure")
INJECTION = "*/ int injected; /*\n\"\"\"\nraise SystemExit('injected')\n'''\\"


def four_bar() -> eg.System:
    return load(Path(__file__).parents[1] / "examples" / "four_bar.py").four_bar()


def two_branches(kind: str, tip: str = "tip", end: str = "end", name: str | None = None) -> eg.System:
    """A revolute-revolute arm and a body on a ball joint, the arm's tip joined to the body's end."""
    system = eg.System(gravity=(0, 0, -9.81))
    inertia = np.diag([0.1, 0.2, 0.25])
    system.add_body("a1", joint=eg.Revolute("q1", axis=(0, 0, 1)), mass=1, com=(0.2, 0, 0), inertia=inertia)
    system.add_body("a2", parent="a1", joint=eg.Revolute("q2", axis=(0, 1, 0)), mass=1, com=(0.2, 0, 0),
                    inertia=inertia, placement=eg.Placement(translation=(0.5, 0, 0)))
    system.add_body("b1", joint=eg.Spherical("ball"), mass=1, com=(0, 0, 0.2), inertia=inertia,
                    placement=eg.Placement(translation=(0.6, 0.4, 0)))
    system.add_frame(tip, "a2", eg.Placement(translation=(0.4, 0, 0)))
    system.add_frame(end, "b1", eg.Placement(translation=(0, 0, 0.5)))
    system.add_loop(tip, end, kind=kind, name=name)
    return system


def numpy_outputs(f, q, u) -> list[np.ndarray]:
    """J_c, J̇_c u and (with loops or disks) the closure residual of the NumPy functions at one state."""
    out = [f.contact_jacobian(q), f.contact_jacobian_dot_u(q, u)]
    return out + [f.closure_residual(q)] if f.closure_rows else out


def module_outputs(m, q, u) -> list[np.ndarray]:
    out = [m.contact_jacobian(q), m.contact_jacobian_dot_u(q, u)]
    return out + [m.closure_residual(q)] if hasattr(m, "closure_residual") else out


def plain_c(eom, directory: Path, q: np.ndarray, u: np.ndarray) -> tuple[list[list[np.ndarray]], str]:
    """write_c's constraint functions compiled (-Wall -Werror) with a driver that prints them at each state
    (out sized from the header's 'out: rows x cols'); per state the outputs, and the header."""
    _, h = eg.write_c(eom, directory, name="sys")
    header = h.read_text()
    shapes = {key: (int(r), int(c)) for r, c, key in
              re.findall(r"out: (\d+) x (\d+), row-major; reads [^\n]*\*/\nvoid sys_(\w+)\(", header)}
    keys = [k for k in KEYS if k in shapes]
    rows = ",\n".join("{" + ", ".join(repr(float(x)) for x in v) + "}" for v in (*q, *u))
    calls = [f"{{ double out[{shapes[k][0] * shapes[k][1]}] = {{0}}; sys_{k}(X[k], X[N + k], ud, p, out);\n"
             f'  for (int i = 0; i < {shapes[k][0] * shapes[k][1]}; ++i) printf("%.17g ", out[i]); }}'
             for k in keys]
    (directory / "driver.c").write_text(
        f'#include <stdio.h>\n#include "sys.h"\nenum {{ N = {len(q)} }};\n'
        f"static const double X[2 * N][{max(q.shape[1], u.shape[1])}] = {{\n{rows}}};\n"
        "int main(void) {\n  double ud[SYS_NV + 1] = {0}, p[SYS_NP + 1] = {0};\n"
        "  for (int k = 0; k < N; ++k) {\n" + "\n".join(calls) + '\n  printf("\\n");\n  }\n  return 0;\n}\n')
    exe = directory / "driver"
    subprocess.run(["cc", "-Wall", "-Werror", str(directory / "driver.c"), str(directory / "sys.c"), "-o",
                    str(exe), "-lm"], check=True)
    lines = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.strip().split("\n")
    sizes = np.cumsum([shapes[k][0] * shapes[k][1] for k in keys])[:-1]
    return [[x.reshape(shapes[k]) for k, x in zip(keys, np.split(np.array(line.split(), float), sizes))]
            for line in lines], header


def assert_paths_agree(system: eg.System, q: np.ndarray, u: np.ndarray, directory: Path) -> tuple:
    """At each state the module's and plain C's outputs = NumPy's to 1e-13 (of the largest entry, or 1);
    the module in a batch too. Returns (NumPy's outputs per state, the module, the header)."""
    eom = eg.derive(system, method="recursive")
    f = eg.codegen(eom)
    m = load(eg.write_module(eom, directory / "constrained.py"))
    c, header = plain_c(eom, directory, q, u)
    expected = [numpy_outputs(f, q[k], u[k]) for k in range(len(q))]
    assert m.CONSTRAINT_ROWS == f.constraint_rows and getattr(m, "CLOSURE_ROWS", []) == f.closure_rows
    for label, got in [("module", [module_outputs(m, q[k], u[k]) for k in range(len(q))]), ("write_c", c),
                       ("module, batch", list(zip(*module_outputs(m, q, u))))]:
        for k, (outs, refs) in enumerate(zip(got, expected)):
            assert len(outs) == len(refs), label
            for key, x, ref in zip(KEYS, outs, refs):
                scale = max(1.0, np.abs(ref).max())
                np.testing.assert_allclose(x.reshape(ref.shape), ref, rtol=1e-13, atol=1e-13 * scale,
                                           err_msg=f"{label} {key} {k}")
    return expected, m, header


def states(system: eg.System, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    q, u, _ = eg.random_states(system, n, np.random.default_rng(seed))
    return q, u


@pytest.mark.parametrize("build", [four_bar, lambda: two_branches("point"), lambda: two_branches("frame")],
                         ids=["four-bar (revolute loop)", "two branches (point)", "two branches (frame)"])
def test_loops_on_every_path(build, tmp_path):
    system = build()
    q, u = states(system, 4, 7)
    _, m, header = assert_paths_agree(system, q, u, tmp_path)
    for row in m.CONSTRAINT_ROWS:  # the rows by name in the header, under J_c, J̇_c u and the closure
        assert header.count(f": {row}\n") == 3, row


def test_rolling_disk_on_every_path_equals_its_closed_forms(tmp_path):
    system = disk()
    rng = np.random.default_rng(11)
    q, u = rng.uniform(-1.2, 1.2, (4, 6)), rng.uniform(-2, 2, (4, 6))  # no disk lying flat
    expected, m, header = assert_paths_agree(system, q, u, tmp_path)
    assert m.CONSTRAINT_ROWS == ["wheel_rolling.t1", "wheel_rolling.t2", "wheel_rolling.n"]
    assert m.CLOSURE_ROWS == ["wheel_rolling.height"] and "row 0: wheel_rolling.height\n" in header
    for k, (J, _, height) in enumerate(expected):
        z, v = closed_forms(q[k], u[k])
        assert np.isclose(height[0], z, atol=1e-14) and np.allclose(J @ u[k], v, atol=1e-13)


@settings(max_examples=4, **COMMON)
@given(case=loops())
def test_random_trees_with_a_loop_on_every_path(case):
    """Random trees (adversarial names) with a point or frame loop closed at a drawn state: every path
    agrees there and at two random states, and the residual vanishes at the closed state."""
    tree, a, b, kind, seed = case
    rng = np.random.default_rng(seed)
    system, q0, u0 = closed_tree(tree, kind, a, b, rng)
    drawn = [S.random_state(tree, rng) for _ in range(2)]
    q, u = np.array([q0, *(x for x, _ in drawn)]), np.array([u0, *(v for _, v in drawn)])
    with tempfile.TemporaryDirectory() as directory:
        expected, _, _ = assert_paths_agree(system, q, u, Path(directory))
    assert np.allclose(expected[0][2], 0, atol=1e-10)


def test_row_names_cannot_inject_code(tmp_path):
    """A loop named with every adversarial name and a code injection, between frames so named: the module
    imports and holds the names as they are; the header's comments hold them, the compiler sees none."""
    name = "".join(S.ALPHABET) + INJECTION
    system = two_branches("point", tip="*/", end="a\nb" + INJECTION, name=name)
    q, u = states(system, 2, 3)
    _, m, header = assert_paths_agree(system, q, u, tmp_path)
    assert m.CONSTRAINT_ROWS == [f"{name}.{x}" for x in "xyz"] == m.CLOSURE_ROWS
    source = (tmp_path / "constrained.py").read_text()
    names = {node.id for node in ast.walk(ast.parse(source)) if isinstance(node, ast.Name)}
    assert "injected" not in names and "SystemExit" not in names
    code = re.sub(r"/\*.*?\*/", "", header, flags=re.S)  # what the compiler sees
    assert "injected" not in code and header.count("*/") == header.count("/*")
    assert header.count("int injected; /?") == 3 * 3 + 3  # 3 rows × 3 functions, the frame's J, J̇u, X


def test_equations_of_a_system_changed_since_are_refused(tmp_path):
    """A loop added after the derivation: neither output is written without it."""
    system = four_bar()
    eom = eg.derive(system, method="recursive")
    system.add_loop("crank", "rocker_end", kind="point", name="second")
    for write in (lambda: eg.write_module(eom, tmp_path / "m.py"), lambda: eg.write_c(eom, tmp_path)):
        with pytest.raises(eg.ModelError, match="the system changed after these equations were derived"):
            write()
