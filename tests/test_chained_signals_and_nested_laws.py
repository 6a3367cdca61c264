"""Symbolic work stays polynomial in the nesting a model file asks for (issue 25, item 5): twenty
chained controllers ``c_i = c_{i+1} + sin(c_{i+1})`` printed an equations report of exponential size
(each output written out through all the later ones), and a driver law of six nested ``abs`` derived
for over 200 s (each ``abs(x)`` became ``piecewise(x, x >= 0, -x)`` before differentiation, three
copies of x per level).

Each check runs in a child interpreter with a timeout, so that a regression fails instead of hanging
the suite; the assertions are on sizes (characters of the report, nodes of the derivatives), never on
elapsed time."""

import json
import subprocess
import sys
import textwrap

from child_env import child_env

#: A pendulum whose torque is the first of ``n`` chained controller outputs, the last one a PD law of
#: the pendulum; a controller state integrates the first output (its printed rate names it).
PENDULUM = """
name = "chained-controllers"
[bodies.bob]
mass = 1.0
inertia = 0.1
points = { pin = [-0.5, 0] }
[joints.pin]
type = "revolute"
parent = "ground"
child = "bob"
child_point = "pin"
torque = "-c1 - 0.1*zc"
[gravity]
g = 9.81
direction = [0, -1]
[controllers.integral]
states = { zc = "c1" }
"""

#: A pendulum carried by a hub whose angle is a driver law (``{law}``): the elbow is free.
DRIVEN = """
name = "nested-abs-driver"
[bodies.hub]
mass = 1.0
inertia = 0.1
points = {{ pin = [-0.5, 0] }}
[bodies.arm]
mass = 0.5
inertia = 0.02
points = {{ pin = [-0.3, 0] }}
[joints.hub]
type = "revolute"
parent = "ground"
child = "hub"
child_point = "pin"
driver = {{ coordinate = "{law}" }}
[joints.elbow]
type = "revolute"
parent = "hub"
parent_point = "pin"
child = "arm"
child_point = "pin"
[gravity]
g = 9.81
direction = [0, -1]
"""

#: Hang guard of each child [s]: the checks take a few seconds; a regression to exponential work
#: takes minutes and fails here rather than blocking the suite.
CHILD_TIMEOUT = 240


def chained_model(n: int) -> str:
    """The text of :data:`PENDULUM` with ``n`` chained controller outputs ``c1 .. c<n>``."""
    controllers = [f'[controllers.c{i}]\noutput = "c{i + 1} + sin(c{i + 1})"' for i in range(1, n)]
    controllers.append(f'[controllers.c{n}]\noutput = "0.5*q_pin + 0.1*u_pin"')
    return PENDULUM + "\n".join(controllers) + "\n"


def nested_abs(n: int) -> str:
    """``abs(abs(... abs(t - 0.01) - 0.01 ...) - 0.01)``: ``n`` nested ``abs``."""
    law = "t - 0.01"
    for _ in range(n):
        law = f"abs({law}) - 0.01"
    return law


def _child(script: str, **texts: str) -> dict:
    """Run ``script`` in a new interpreter with ``texts`` as JSON on stdin; its JSON output."""
    done = subprocess.run([sys.executable, "-c", textwrap.dedent(script)], input=json.dumps(texts),
                          capture_output=True, text=True, timeout=CHILD_TIMEOUT, env=child_env())
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout)


REPORT = """
    import json, sys
    import flexkane
    from flexkane.kane.equations import derive
    from flexkane.report import equations_markdown, format_equations

    out = {}
    for key, text in json.load(sys.stdin).items():
        eom = derive(flexkane.loads_model(text))
        out[key] = {"markdown": len(equations_markdown(eom)), "text": format_equations(eom)}
    print(json.dumps(out))
"""


def test_the_report_of_chained_controllers_grows_linearly_with_the_chain():
    sizes = _child(REPORT, short=chained_model(10), long=chained_model(20))
    short, long = sizes["short"], sizes["long"]
    # ten more outputs of a few dozen characters each: linear growth (2^10 times larger before)
    assert long["markdown"] - short["markdown"] < 10 * 400, (short["markdown"], long["markdown"])
    assert long["markdown"] < 20_000
    lines = long["text"].splitlines()
    # each output written once, naming the next one; the state's rate names c1
    assert "c1 = c2 + sin(c2)" in lines and "c19 = c20 + sin(c20)" in lines
    assert "zc' = c1" in lines


NESTED = """
    import json, sys
    import sympy as sp
    import flexkane
    from flexkane.expressions import parse_expression, time_derivative
    from flexkane.kane.equations import derive
    from flexkane.report import equations_markdown

    texts = json.load(sys.stdin)
    t = sp.Symbol("t", real=True)
    nodes = {}
    for n in (3, 6, 12):
        law = parse_expression(texts[f"law{n}"], {"t": t}, path="joints.hub.driver.coordinate")
        first = time_derivative(law, t, path="p")
        second = time_derivative(law, t, path="p", order=2)
        nodes[n] = [sum(1 for _ in sp.preorder_traversal(e)) for e in (law, first, second)]
        # the derivative at sample times against a centred difference of the law (away from kinks)
        f, d = sp.lambdify(t, law), sp.lambdify(t, first)
        nodes[f"check{n}"] = [(float(d(s)), (float(f(s + 1e-7)) - float(f(s - 1e-7))) / 2e-7)
                              for s in (0.0031, 0.017, 0.033, 0.5)]
    eom = derive(flexkane.loads_model(texts["model"]))
    print(json.dumps({"nodes": nodes, "markdown": len(equations_markdown(eom))}))
"""


def test_a_driver_law_of_nested_abs_derives_in_a_size_polynomial_in_the_nesting():
    found = _child(NESTED, law3=nested_abs(3), law6=nested_abs(6), law12=nested_abs(12),
                   model=DRIVEN.format(law=nested_abs(6)))
    nodes = found["nodes"]
    for n in (3, 6, 12):
        law, first, second = nodes[str(n)]
        # the law has O(n) nodes; its derivative one branch sign per level, each naming its argument
        # (O(n^2) nodes); the second derivative of a piecewise linear law is 0
        assert law <= 6 * n + 6 and first <= 6 * n * n + 20 and second == 1, (n, nodes[str(n)])
        for exact, difference in nodes[f"check{n}"]:
            assert abs(exact - difference) < 1e-6
    assert found["markdown"] < 20_000
